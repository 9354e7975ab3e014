"""The exported source and the example sketch refuse a header of another export (issue 27).

Two missions are exported into two folders. pampipe_plan.c is compiled by the host's gcc (the
strict flags of tests/support/export_c.py) against its own header and against the other export's. The
sketch (an Arduino .ino, C++) is compiled by g++ as C++ with a stub of the few Arduino names it uses
(``-include`` of :data:`ARDUINO_STUB`, ``-fsyntax-only``): this checks the preprocessor's hash test and
that the sketch is valid C++ against those declarations, not that it builds with the real Arduino
core (tests/export/test_avr.py does that where arduino-builder is installed).
"""

from __future__ import annotations

import re
import shutil
import subprocess

import pytest

from pampipe.export import Provenance, generate
from pampipe.io.mission_schema import load_mission
from tests.support import export_c
from tests.support.problems import PROBLEMS

ARDUINO_STUB = """\
#include <stdint.h>
#define HIGH 1
#define LOW 0
#define OUTPUT 1
enum { A0 = 54, A1, A2 };
int analogRead(uint8_t pin);
void digitalWrite(uint8_t pin, uint8_t value);
void pinMode(uint8_t pin, uint8_t mode);
unsigned long millis(void);
struct SerialPort {
    void begin(unsigned long baud);
    void print(const char *text);
    void print(double value, int digits);
    void println(const char *text);
    void println(int value);
};
extern SerialPort Serial;
"""
SKETCH = "firmware.ino"


@pytest.fixture(scope="module")
def folders(tmp_path_factory):
    """{mission stem: folder} of two exports of different missions."""
    out = {}
    for stem in ("vertical-climb-3in", "downhill-drain"):
        mission = load_mission(PROBLEMS / "missions" / f"{stem}.yaml")
        export = generate(mission, provenance=Provenance(str(mission.source), ()), sketch_name="firmware")
        folder = tmp_path_factory.mktemp(stem)
        for name, text in export.files.items():
            (folder / name).write_text(text)
        out[stem] = folder
    return out


def _hash(folder, name):
    return re.findall(r"0x[0-9a-f]{15}", (folder / name).read_text())


def test_every_file_carries_the_same_hash(folders):
    for folder in folders.values():
        header = _hash(folder, "pampipe_plan.h")
        assert len(set(header)) == 1
        assert set(_hash(folder, "pampipe_plan.c")) == set(header) == set(_hash(folder, SKETCH))
    one, two = folders.values()
    assert _hash(one, "pampipe_plan.h") != _hash(two, "pampipe_plan.h")


def _mixed(name, source_folder, header_folder, tmp_path):
    """A folder holding ``name`` of one export beside the header of another (as a half-copied folder
    would: ``#include "..."`` looks beside the file first, so the pair must share a folder)."""
    folder = tmp_path / f"{source_folder.name}+{header_folder.name}"
    folder.mkdir(exist_ok=True)
    shutil.copy(source_folder / name, folder / name)
    shutil.copy(header_folder / "pampipe_plan.h", folder / "pampipe_plan.h")
    return folder / name


def _compile_source(source_folder, header_folder, tmp_path):
    source = _mixed("pampipe_plan.c", source_folder, header_folder, tmp_path)
    return subprocess.run([export_c.compiler(), *export_c.FLAGS, "-c", "-o", str(tmp_path / "plan.o"),
                           str(source)], capture_output=True, text=True)


def _compile_sketch(sketch_folder, header_folder, tmp_path):
    stub = tmp_path / "arduino_stub.h"
    stub.write_text(ARDUINO_STUB)
    sketch = _mixed(SKETCH, sketch_folder, header_folder, tmp_path)
    return subprocess.run([shutil.which("g++"), "-fsyntax-only", "-Wall", "-Werror", "-x", "c++", "-include",
                           str(stub), str(sketch)], capture_output=True, text=True)


@pytest.mark.skipif(export_c.compiler() is None, reason="no host C compiler")
def test_source_refuses_another_exports_header(folders, tmp_path):
    one, two = folders["vertical-climb-3in"], folders["downhill-drain"]
    assert _compile_source(one, one, tmp_path).returncode == 0
    mixed = _compile_source(one, two, tmp_path)
    assert mixed.returncode != 0
    assert "#error" in mixed.stderr and "another export" in mixed.stderr


@pytest.mark.skipif(shutil.which("g++") is None, reason="no host C++ compiler")
def test_sketch_refuses_another_exports_header(folders, tmp_path):
    one, two = folders["vertical-climb-3in"], folders["downhill-drain"]
    for folder in (one, two):
        own = _compile_sketch(folder, folder, tmp_path)
        assert own.returncode == 0, own.stderr
    for sketch, header in ((one, two), (two, one)):
        mixed = _compile_sketch(sketch, header, tmp_path)
        assert mixed.returncode != 0
        assert "#error" in mixed.stderr and "another export than this sketch" in mixed.stderr
