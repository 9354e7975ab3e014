"""Pipe bores from standard sizes, with a tolerance (docs/commands.md §4.3).

:func:`bore` reads the value of a route section's ``inner_diameter`` key, already parsed from YAML, and
returns the bore range in metres. Four forms are accepted:

* a length: ``3 in``, ``76.2 mm`` or a bare number in metres;
* ``{value: 76.2 mm}``;
* ``{nps: 3, schedule: 40}``: steel pipe, ASME B36.10M (schedules 5 to 160, STD, XS, XXS) and B36.19M
  (5S, 10S, 40S, 80S). The table is the ``fluids`` package's (``fluids.piping``), which stores the metric
  columns of both standards: wall to 0.01 mm, outside diameter to 0.1 mm up to NPS 12 and to 1 mm above.
  Its bores therefore differ from the inch columns by up to 0.06 mm up to NPS 12 (NPS 3 Sch 40: 77.92 mm
  here, 3.068 in = 77.927 mm there) and up to 0.4 mm (0.07 %) above (NPS 24: 610 mm for 24 in), far
  inside the mill tolerances of steel pipe (wall -12.5 %, ASTM A53/A106);
* ``{dn: 110, sdr: 11}``: plastic pipe (PE, PVC-U) sized by its outside diameter, ISO 4065/4427/1452
  and EN 12201: ``dn`` is the nominal outside diameter in millimetres and SDR = dn / wall, so the bore is
  ``dn - 2 dn / SDR`` (DN 110 SDR 11: wall 10.0 mm, bore 90.0 mm). The standards' tables take the wall
  from the exact preferred-number series and round it up to 0.1 mm, so a tabulated bore may differ by a
  few tenths of a millimetre (DN 63 SDR 11: 51.55 mm here, 63 - 2 x 5.8 = 51.4 mm in the table), and real
  pipe has a wall up to about 10 % thicker (ISO 11922-1): give a ``tolerance`` that covers it. Plastic
  pipe sized by inch outside diameters (IPS, CIOD: ASTM F714, AWWA C900) is not covered.

Each mapping may add ``tolerance``, a length (``1 mm``) or a percentage of the bore (``2 %``), giving the
range [bore - tolerance, bore + tolerance], and ``sd``, the standard deviation of the bore (a length or a
percentage) for confidence plans.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from fractions import Fraction

from pampipe.errors import InputError
from pampipe.units.quantities import to_si

#: ASME schedules, as ``fluids.piping`` names them: B36.10M, then B36.19M (stainless, suffix S).
STAINLESS = ("5S", "10S", "40S", "80S")
SCHEDULES = ("5", "10", "20", "30", "40", "60", "80", "100", "120", "140", "160", "STD", "XS", "XXS",
             *STAINLESS)
MAX_BORE = 10.0  # [m] the largest inner diameter any mission accepts (as for a plain length)
_PERCENT = re.compile(r"^\s*([0-9]*\.?[0-9]+(?:[eE][-+]?[0-9]+)?)\s*%\s*$")
_FORMS = {"value": ("value",), "nps": ("nps", "schedule"), "dn": ("dn", "sdr")}
_OPTIONAL = ("tolerance", "sd")


@dataclass(frozen=True)
class BoreSpec:
    """A pipe bore [m]: the nominal value, the range it may take, and its standard deviation."""

    nominal: float  # [m]
    low: float  # [m] nominal - tolerance
    high: float  # [m] nominal + tolerance
    label: str  # what the user asked for, e.g. "NPS 3 Sch 40 (ASME B36.10M) ± 1 mm"
    sd: float = 0.0  # [m] standard deviation of the bore (0 = known exactly)

    def as_document(self) -> dict:
        """JSON keys of a planned section (docs/commands.md §4.3), SI with unit suffixes."""
        return {"inner_diameter_m": self.nominal, "inner_diameter_range_m": [self.low, self.high],
                "inner_diameter_sd_m": self.sd, "inner_diameter_label": self.label}


def bore(spec: object, *, where: str = "inner_diameter") -> BoreSpec:
    """The bore [m] that ``spec`` (a length or a mapping, see the module docstring) describes.

    Raises :class:`InputError` naming ``where``, the bad value and what is allowed.
    """
    if not isinstance(spec, dict):
        nominal = _length(spec, where)
        return BoreSpec(nominal, nominal, nominal, _shown(spec))
    form = _form(spec, where)
    if form == "value":
        nominal = _length(spec["value"], f"{where}.value")
        label = _shown(spec["value"])
    elif form == "nps":
        nominal, label = _steel(spec["nps"], spec["schedule"], where)
    else:
        nominal, label = _plastic(spec["dn"], spec["sdr"], where)
    tolerance = _share(spec.get("tolerance", 0.0), nominal, f"{where}.tolerance")
    if tolerance >= nominal:
        raise InputError(f"{where}.tolerance: {_mm(tolerance)} is not smaller than the bore {_mm(nominal)}; "
                         "give the bore's tolerance, e.g. '1 mm' or '2 %'.")
    sd = _share(spec.get("sd", 0.0), nominal, f"{where}.sd")
    if "tolerance" in spec:
        label += f" ± {_shown(spec['tolerance'])}"
    if "sd" in spec:
        label += f", sd {_shown(spec['sd'])}"
    return BoreSpec(nominal, nominal - tolerance, nominal + tolerance, label, sd)


def _form(spec: dict, where: str) -> str:
    """Which of the three mapping forms ``spec`` uses; every other key is an error."""
    forms = [name for name, keys in _FORMS.items() if any(k in spec for k in keys)]
    allowed = "{value: 76.2 mm}, {nps: 3, schedule: 40} or {dn: 110, sdr: 11}, each with optional " \
              "tolerance: (e.g. '1 mm' or '2 %') and sd:"
    if len(forms) != 1:
        given = ", ".join(map(str, spec)) or "nothing"
        raise InputError(f"{where}: give exactly one of {allowed}; got keys {given}.")
    form = forms[0]
    missing = [k for k in _FORMS[form] if k not in spec]
    if missing:
        raise InputError(f"{where}: {form}: also needs {' and '.join(missing)}, as in {allowed}.")
    unknown = [str(k) for k in spec if k not in _FORMS[form] + _OPTIONAL]
    if unknown:
        raise InputError(f"{where}: unknown key {', '.join(unknown)}; allowed here: "
                         f"{', '.join(_FORMS[form] + _OPTIONAL)}.")
    return form


def _steel(nps_value: object, schedule_value: object, where: str) -> tuple[float, str]:
    """Bore [m] and label of ASME NPS ``nps_value`` in ``schedule_value``, from ``fluids.piping``."""
    from fluids.piping import nearest_pipe, schedule_lookup

    nps = _nps(nps_value, where)
    schedule = _schedule(schedule_value, where)
    sizes = schedule_lookup[schedule][0]
    if nps not in sizes:
        offered = [s for s in SCHEDULES if nps in schedule_lookup[s][0]]
        if offered:
            raise InputError(f"{where}: NPS {_fraction(nps)} has no schedule {schedule}; its schedules are "
                             f"{', '.join(offered)}.")
        every = sorted({n for s in SCHEDULES for n in schedule_lookup[s][0]})
        raise InputError(f"{where}.nps: {nps_value!r} is not a standard pipe size (ASME B36.10M/B36.19M); "
                         f"sizes are {', '.join(map(_fraction, every))}.")
    inner = nearest_pipe(NPS=nps, schedule=schedule)[1]
    standard = "ASME B36.19M" if schedule in STAINLESS else "ASME B36.10M"
    return inner, f"NPS {_fraction(nps)} Sch {schedule} ({standard})"


def _nps(value: object, where: str) -> float:
    """A nominal pipe size: a number or a fraction such as ``1/8``, ``1 1/4`` or ``1-1/4``."""
    try:
        if isinstance(value, bool):
            raise ValueError
        if isinstance(value, int | float):
            size = Fraction(value)
        elif isinstance(value, str):
            whole, _, part = re.sub(r"(\d)-(\d)", r"\1 \2", value.strip()).rpartition(" ")
            size = Fraction(whole or 0) + Fraction(part)
        else:
            raise ValueError
    except (ValueError, ZeroDivisionError, OverflowError):
        raise InputError(f"{where}.nps: {value!r} is not a nominal pipe size; write e.g. 3, 0.5, 1/8 or "
                         "1 1/4.") from None
    return float(size)


def _schedule(value: object, where: str) -> str:
    """A schedule name as fluids knows it: 40 and 'Sch 40' become '40', 'std' becomes 'STD'."""
    if isinstance(value, int | float) and not isinstance(value, bool) and float(value).is_integer():
        name = str(int(value))
    else:
        name = re.sub(r"^SCH(EDULE)?", "", str(value).strip().upper()).strip()
    if name not in SCHEDULES:
        raise InputError(f"{where}.schedule: {value!r} is not an ASME schedule; allowed: "
                         f"{', '.join(SCHEDULES)}.")
    return name


def _plastic(dn_value: object, sdr_value: object, where: str) -> tuple[float, str]:
    """Bore [m] and label of plastic pipe of outside diameter ``dn_value`` [mm] and ratio ``sdr_value``."""
    dn = _number(dn_value, f"{where}.dn", "the nominal outside diameter in mm, e.g. 110")
    sdr = _number(sdr_value, f"{where}.sdr", "the standard dimension ratio outside diameter / wall, e.g. 11")
    if not 0 < dn <= MAX_BORE * 1e3:
        raise InputError(f"{where}.dn: {dn_value!r} is out of range; give the outside diameter in mm, "
                         f"between 0 and {MAX_BORE * 1e3:g}.")
    if not sdr > 2:
        raise InputError(f"{where}.sdr: {sdr_value!r} leaves no bore (SDR = outside diameter / wall must "
                         "exceed 2); standard ratios are 6, 7.4, 9, 11, 13.6, 17, 21, 26, 33, 41.")
    return (dn - 2 * dn / sdr) * 1e-3, f"DN {dn:g} SDR {sdr:g}"


def _number(value: object, where: str, meaning: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise InputError(f"{where}: expected a number, {meaning}; got {value!r}.")
    return float(value)


def _length(value: object, where: str) -> float:
    """A bore given as a length [m], in (0, MAX_BORE]."""
    length = to_si(value, "length", where=where)
    if not 0 < length <= MAX_BORE:
        raise InputError(f"{where}: {value!r} is not a pipe bore; give a length between 0 and "
                         f"{MAX_BORE:g} m, e.g. '3 in'.")
    return length


def _share(value: object, nominal: float, where: str) -> float:
    """A tolerance or sd [m]: a length, or a percentage of ``nominal`` such as '2 %'."""
    if isinstance(value, str) and "%" in value:
        match = _PERCENT.match(value)
        if not match:
            raise InputError(f"{where}: cannot read {value!r} as a percentage; write e.g. '2 %'.")
        amount = float(match.group(1)) / 100 * nominal
    else:
        amount = to_si(value, "length", where=where)
    if amount < 0:
        raise InputError(f"{where}: {value!r} is negative; give a length such as '1 mm' or a percentage "
                         "of the bore such as '2 %'.")
    return amount


def _fraction(nps: float) -> str:
    """1.25 -> '1 1/4', 0.125 -> '1/8', 3.0 -> '3'."""
    whole, part = divmod(Fraction(nps), 1)
    return " ".join(s for s in (str(whole) if whole else "", str(part) if part else "") if s) or "0"


def _mm(length: float) -> str:
    return f"{length * 1e3:.6g} mm"


def _shown(value: object) -> str:
    return _mm(value) if isinstance(value, int | float) else str(value).strip()


def schedule_bores(low: float, high: float, *, schedule: str = "40") -> list[tuple[str, float]]:
    """[(label, bore [m])] of the ASME steel pipes of ``schedule`` whose bore lies in (low, high)."""
    from fluids.piping import schedule_lookup

    sizes, bores = schedule_lookup[schedule][0], schedule_lookup[schedule][1]
    return [(f"NPS {_fraction(nps)} Sch {schedule}", bore * 1e-3)
            for nps, bore in zip(sizes, bores, strict=True) if low < bore * 1e-3 < high]
