"""Values far outside what a pipe-crawling robot uses: the likely unit slips of a file (docs/formats.md §1).

A value read correctly may still be in the wrong unit: ``supply_pressure: 100 Pa`` written for 100 kPa, or
``mass: 400 kg`` for 400 g. Such values are valid, so they are not refused, but each gets a warning naming
the key, the value in SI and the slip it suggests. The ranges are wide: a real robot is never near them.
"""

from __future__ import annotations

#: Lowest plausible supply [Pa] (gauge): no muscle anchors below 1 kPa; 100 Pa is 100 kPa in the wrong unit.
LOWEST_SUPPLY = 1e3
#: Highest plausible supply [Pa]: 10 MPa is beyond any pneumatic muscle (1450 psi).
HIGHEST_SUPPLY = 1e7
#: Heaviest plausible segment [kg]: a muscle with its fittings weighs grams to kilograms.
HEAVIEST_SEGMENT = 100.0
#: Heaviest plausible payload [kg].
HEAVIEST_PAYLOAD = 1000.0


def unit_slips(supply: float, masses: dict[str, float], payload: float) -> tuple[str, ...]:
    """Warnings for a ``supply`` [Pa], segment ``masses`` {key: kg} and ``payload`` [kg] far outside their
    plausible range, each naming the likely unit slip."""
    out = []
    if 0 < supply < LOWEST_SUPPLY:
        out.append(f"supply_pressure is {supply:g} Pa, below {LOWEST_SUPPLY / 1e3:g} kPa: was it meant in "
                   f"kPa or psi ({supply:g} kPa, {supply:g} psi)? In a file with 'units: SI' a bare number is"
                   " Pa.")
    if supply > HIGHEST_SUPPLY:
        out.append(f"supply_pressure is {supply / 1e6:g} MPa, above {HIGHEST_SUPPLY / 1e6:g} MPa: was it "
                   "meant in Pa or kPa?")
    for key, mass in masses.items():
        if mass > HEAVIEST_SEGMENT:
            out.append(f"{key} is {mass:g} kg, above {HEAVIEST_SEGMENT:g} kg for one segment: was it meant "
                       f"in g ({mass:g} g = {mass / 1e3:g} kg)?")
    if payload > HEAVIEST_PAYLOAD:
        out.append(f"robot.payload is {payload:g} kg, above {HEAVIEST_PAYLOAD:g} kg: was it meant in g or "
                   "lb?")
    return tuple(out)
