"""`pampipe export` on the robot's chip: the ATmega2560 of an Arduino Mega.

The tools come from Debian's packages, which .ci/run installs in CI:

* avr-gcc + simavr (``apt-get install gcc-avr avr-libc simavr``): the exported C is built for the
  ATmega2560 in float, one call runs in the simulator at 16 MHz, and the answer is compared with
  `plan` (1e-4 relative, the float tolerance of tests/export/test_export.py). Timer 1 counts the call's
  cycles; flash and RAM come from avr-size. The numbers are printed (``pytest -s``).
* arduino-builder + arduino-core-avr (``apt-get install arduino-builder arduino-core-avr
  arduino-ctags``): the example sketch compiles for the Mega.

Without the tools these tests skip and say which packages are missing; the host tests still run.
"""

from __future__ import annotations

import math
import re
import shutil
import struct
import subprocess
from pathlib import Path

import pytest

from pampipe.export import Provenance, generate
from pampipe.io.mission_schema import load_mission
from pampipe.planning import plan_mission
from tests.support.problems import PROBLEMS

MISSION = PROBLEMS / "missions" / "vertical-climb-3in.yaml"
AVR_FLAGS = ["-mmcu=atmega2560", "-Os", "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror",
             "-DPAMPIPE_REAL_FLOAT", "-DF_CPU=16000000UL"]
ARDUINO = Path("/usr/share/arduino/hardware")

FIRMWARE = r"""
#include <avr/interrupt.h>
#include <avr/io.h>
#include <avr/sleep.h>
#include "pampipe_plan.h"

static volatile unsigned int overflows;
ISR(TIMER1_OVF_vect) { ++overflows; }

/* the section, volatile so that the compiler cannot fold the call */
volatile pampipe_real input[4] = {INPUTS};

static void put(char c) { while (!(UCSR0A & (1 << UDRE0))) { } UDR0 = c; }
static void put_hex(unsigned long v)
{
    int i;
    for (i = 28; i >= 0; i -= 4) { put("0123456789abcdef"[(v >> i) & 15]); }
}

int main(void)
{
    pampipe_real p[PAMPIPE_SEGMENTS];
    unsigned int ticks;
    unsigned long cycles;
    int code, i;
    UBRR0 = 0;
    UCSR0B = (1 << TXEN0);
    TCCR1A = 0;
    TIMSK1 = (1 << TOIE1);
    sei();
    TCNT1 = 0;
    TCCR1B = (1 << CS10); /* count every CPU cycle */
    code = pampipe_required_pressure(input[0], input[1], input[2], input[3], p);
    ticks = TCNT1;
    TCCR1B = 0;
    cli();
    cycles = ((unsigned long)overflows << 16) + ticks;
    if ((TIFR1 & (1 << TOV1)) && ticks < 32768u) { cycles += 65536ul; } /* an overflow not yet counted */
    put_hex((unsigned long)code); put(' ');
    put_hex(cycles);
    for (i = 0; i < PAMPIPE_SEGMENTS; ++i) {
        union { pampipe_real r; unsigned long u; } bits;
        bits.r = p[i];
        put(' '); put_hex(bits.u);
    }
    put('\n');
    sleep_cpu(); /* interrupts off: simavr stops here */
    return 0;
}
"""


def _missing(*tools: str) -> list[str]:
    return [t for t in tools if shutil.which(t) is None]


def _export(folder: Path):
    mission = load_mission(MISSION)
    export = generate(mission, provenance=Provenance(str(MISSION), ()), sketch_name=folder.name)
    folder.mkdir(parents=True, exist_ok=True)
    for name, text in export.files.items():
        (folder / name).write_text(text)
    return mission, export


def test_one_call_on_the_atmega2560(tmp_path):
    missing = _missing("avr-gcc", "avr-size", "simavr")
    if missing:
        pytest.skip(f"{', '.join(missing)} not found: apt-get install gcc-avr avr-libc simavr")
    mission, _ = _export(tmp_path)
    riser = mission.route[0]
    inputs = (riser.diameter, riser.incline, riser.friction, mission.payload)
    (tmp_path / "main.c").write_text(FIRMWARE.replace("INPUTS", ", ".join(f"{v!r}f" for v in inputs)))
    subprocess.run(["avr-gcc", *AVR_FLAGS, "-fstack-usage", "-c", "-o", str(tmp_path / "pampipe_plan.o"),
                    str(tmp_path / "pampipe_plan.c")], check=True, cwd=tmp_path)
    elf = tmp_path / "firmware.elf"
    subprocess.run(["avr-gcc", *AVR_FLAGS, "-I", str(tmp_path), "-o", str(elf), str(tmp_path / "main.c"),
                    str(tmp_path / "pampipe_plan.o"), "-lm"], check=True)
    run = subprocess.run(["simavr", "-m", "atmega2560", "-f", "16000000", str(elf)], capture_output=True,
                         text=True, timeout=600)
    line = re.search(r"([0-9a-f]{8}(?: [0-9a-f]{8})+)", run.stdout + run.stderr).group(1).split()
    reason, cycles = int(line[0], 16), int(line[1], 16)
    pressure = [struct.unpack("<f", struct.pack("<I", int(v, 16)))[0] for v in line[2:]]
    planned = [s.pressure for s in plan_mission(mission).sections[0].segments]
    assert reason == 0
    assert pressure == pytest.approx(planned, rel=1e-4)  # float, as on the host
    listing = subprocess.run(["avr-size", "-A", str(tmp_path / "pampipe_plan.o")], capture_output=True,
                             text=True, check=True).stdout
    size = {m[0]: int(m[1]) for m in re.findall(r"^(\.\S+)\s+(\d+)", listing, re.MULTILINE)}
    code = size.get(".text", 0)
    tables = sum(v for k, v in size.items() if k.startswith((".rodata", ".data")))  # avr-gcc copies to SRAM
    stack = (tmp_path / "pampipe_plan.su").read_text().split()[-2]
    print(f"\nATmega2560 @ 16 MHz, avr-gcc -Os, float: pampipe_plan.o code {code} B flash; const tables "
          f"{tables} B (flash, and SRAM: avr-gcc copies .rodata to RAM); .bss {size.get('.bss', 0)} B; "
          f"stack of pampipe_required_pressure {stack} B; one call {cycles} cycles = {cycles / 16e3:.3f} ms; "
          f"pressures {pressure} Pa vs plan {planned}")
    assert math.isfinite(cycles) and 0 < cycles < 16_000_000  # under a second: it ran and was timed


def test_example_sketch_compiles_for_an_arduino_mega(tmp_path):
    missing = _missing("arduino-builder", "arduino-ctags", "avr-gcc")
    if missing or not (ARDUINO / "arduino" / "avr").is_dir():
        pytest.skip("arduino-builder, arduino-ctags or the AVR core not found: apt-get install "
                    "arduino-builder arduino-core-avr arduino-ctags gcc-avr avr-libc")
    sketch = tmp_path / "riser_bot"
    _export(sketch)
    build = tmp_path / "build"
    build.mkdir()
    ctags = '"{cmd.path}" -u --language-force=c++ -f - --c++-kinds=svpf --fields=KSTtzns --line-directives ' \
            '"{source_file}"'
    run = subprocess.run([
        "arduino-builder", "-compile", "-hardware", str(ARDUINO), "-tools", "/usr/bin",
        "-fqbn", "arduino:avr:mega:cpu=atmega2560", "-build-path", str(build), "-core-api-version", "10813",
        "-warnings", "all", "-prefs", "tools.ctags.path=/usr/bin",
        "-prefs", "tools.ctags.cmd.path={path}/arduino-ctags", "-prefs", f"tools.ctags.pattern={ctags}",
        # Debian's arduino-core-avr 1.8.7 uses DECIMAL_DIG, which avr-gcc 5.4's C++ <float.h> lacks
        "-prefs", "compiler.cpp.extra_flags=-DDECIMAL_DIG=9",
        str(sketch / "riser_bot.ino")], capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout + run.stderr
    ours = [line for line in (run.stdout + run.stderr).splitlines()
            if ("riser_bot" in line or "pampipe_plan" in line) and "warning" in line]
    assert not ours, ours  # no warning from the exported files or the sketch
    usage = re.findall(r"(Sketch uses \d+ bytes|Global variables use \d+ bytes)", run.stdout)
    print(f"\nexample sketch for the Arduino Mega: {'; '.join(usage)}")
    assert (build / "riser_bot.ino.hex").exists()
