"""The exported law trusts no sensor (issue 27): every argument checked, in C and in Python.

The reference for safety is `plan`'s own model (:func:`tests.support.law_fuzz.unsafe_ok`): an OK answer must
press the muscle on the wall and hold the load with the safety factor. The issue's replay: incline
3.0 rad (cos φ < 0) made the load negative and the C law answered OK with 116.4 kPa, below the
117.0 kPa at which the muscle first touches a 3 in pipe.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pampipe.export import cgen
from pampipe.export.law import Reason
from pampipe.io.mission_schema import load_mission
from tests.support import export_c, law_fuzz
from tests.support.export_c import write_export
from tests.support.problems import PROBLEMS

pytestmark = pytest.mark.skipif(export_c.compiler() is None, reason="no host C compiler (gcc or cc) found")

MISSIONS = ("vertical-climb-3in", "downhill-drain")


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """name -> (mission, export, double driver, float driver), each built once."""
    out = {}
    for name in MISSIONS:
        mission = load_mission(PROBLEMS / "missions" / f"{name}.yaml")
        folder = tmp_path_factory.mktemp(name)
        export = write_export(mission, folder)
        out[name] = (mission, export, export_c.build(folder), export_c.build(folder, real="float"))
    return out


def test_the_issue_replay_is_refused(built):
    _, export, exe, _ = built["vertical-climb-3in"]
    rows = [(0.0762, 3.0, 0.3, 2.0), (0.0762, 10.0, 0.3, 2.0), (0.0762, -math.pi, 0.3, 2.0),
            (0.0762, 0.0, 10.5, 2.0), (0.0762, 0.0, -0.1, 2.0), (0.0762, 0.0, 0.3, 2e5),
            (-0.0762, 0.0, 0.3, 2.0), (11.0, 0.0, 0.3, 2.0), (0.0762, 0.0, 5e-324, 2.0)]
    codes, pressure = export_c.run_law(exe, rows)
    assert codes.tolist() == [5, 5, 5, 5, 5, 5, 5, 5, 3]
    assert np.all(np.isnan(pressure))
    assert [int(export.law.evaluate(*row)[0]) for row in rows] == codes.tolist()
    # the edges themselves are inside: ±90° exactly, μ = 10, m = 10⁵ kg answer with a reason, not 5
    codes, _ = export_c.run_law(exe, [(0.0762, math.pi / 2, 0.3, 0.0), (0.0762, -math.pi / 2, 10.0, 1e5)])
    assert 5 not in codes.tolist()


@pytest.mark.parametrize("name", MISSIONS)
def test_no_unsafe_ok_in_c_or_python(built, name):
    """20 000 random rows (the fuzzer runs 10⁵): never OK outside the domain, or with a slipping pressure."""
    mission, export, exe, _ = built[name]
    rows = law_fuzz.arguments(np.random.default_rng(27), 20_000, export.law)
    codes, pressure = export_c.run_law(exe, rows)
    assert set(codes.tolist()) >= {0, 1, 2, 5}, "the sample must reach OK, the pipe limits and refusals"
    bad = law_fuzz.unsafe_ok(mission, rows, codes, pressure)
    assert not np.any(bad), rows[bad][:5]
    assert np.all(codes[~law_fuzz.in_domain(rows)] == int(Reason.BAD_ARGUMENT))
    twin = [export.law.evaluate(*row) for row in rows[:3000]]
    assert [int(c) for c, _ in twin] == codes[:3000].tolist()
    np.testing.assert_allclose(np.array([p for _, p in twin]), pressure[:3000], rtol=1e-12)


def test_float_build_refuses_alike(built):
    """In float (rows rounded to float first): refusals as in double, OK is safe (the float law rounds up)."""
    mission, export, _, exe = built["vertical-climb-3in"]
    rows = law_fuzz.arguments(np.random.default_rng(28), 5000, export.law)
    with np.errstate(over="ignore"):
        rows = rows.astype(np.float32).astype(float)
    codes, pressure = export_c.run_law(exe, rows)
    # π/2 in float is 1.5707964 > π/2: the float law's edge; compare the domain with that edge
    edge = rows.copy()
    edge[:, 1] = np.where(np.abs(rows[:, 1]) == np.float32(math.pi / 2), np.copysign(math.pi / 2, rows[:, 1]),
                          rows[:, 1])
    bad = law_fuzz.unsafe_ok(mission, edge, codes, pressure)
    assert not np.any(bad), rows[bad][:5]


def test_long_names_are_shortened_in_literals_and_whole_in_comments(tmp_path):
    import yaml

    document = yaml.safe_load((PROBLEMS / "missions" / "vertical-climb-3in.yaml").read_text())
    names = ["\u00e9" * 3000 + "x" * 7000, "\u00e9" * 3000 + "y" * 7000]  # 13 000 bytes, one head
    for section, name in zip(document["route"], names, strict=True):
        section["name"] = name
    document["robot"]["segments"][0]["name"] = "S" * 5000 + "*/ ??= \\"
    for segment in document["robot"]["segments"]:
        segment["pam"] = str(PROBLEMS / "pams" / "paper-radial-pam.yaml")
    path = tmp_path / "long.yaml"
    path.write_text(yaml.safe_dump(document, allow_unicode=True), encoding="utf-8")
    write_export(load_mission(path), tmp_path / "c")
    flags = [*export_c.FLAGS, "-Woverlength-strings"]
    for extra in ([], export_c.FLOAT_FLAGS):
        command = [export_c.compiler(), *flags, *extra, "-c", "-o", str(tmp_path / "x.o"),
                   str(tmp_path / "c" / "pampipe_plan.c")]
        done = export_c.subprocess.run(command, capture_output=True, text=True)
        assert done.returncode == 0, done.stderr[:2000]
    table, segments = export_c.run_table(export_c.build(tmp_path / "c"))
    got = [t["name"] for t in table]
    assert got == [cgen.shortened(n) for n in names] and got[0] != got[1]
    assert all(len(n.encode()) <= cgen.MAX_STRING for n in got + segments)
    source = (tmp_path / "c" / "pampipe_plan.c").read_text()
    unwrapped = source.replace("\n     * ", "")
    assert cgen.comment(names[0]) in unwrapped and cgen.comment(names[1]) in unwrapped
    assert max(len(line) for line in source.splitlines()) < 200


def test_python_law_takes_every_number_and_refuses_the_rest(built):
    from decimal import Decimal
    from fractions import Fraction

    _, export, _, _ = built["vertical-climb-3in"]
    reason, want = export.law.evaluate(0.0762, 1.0, 0.3, 2.0)
    assert reason == Reason.OK
    reason, got = export.law.evaluate(np.array(0.0762), np.float32(1.0), Decimal("0.3"), Fraction(2))
    assert reason == Reason.OK and np.array_equal(got, want)
    for bad in [("0.0762", 1.0, 0.3, 2.0), (0.0762, True, 0.3, 2.0), (0.0762, 10**400, 0.3, 2.0),
                (0.0762, 1.0, 0.3 + 0j, 2.0), (0.0762, 1.0, 0.3, None)]:
        assert export.law.evaluate(*bad)[0] == Reason.BAD_ARGUMENT
