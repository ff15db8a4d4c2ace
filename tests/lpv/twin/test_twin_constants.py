"""The reference's constants come from the table of derivation results without sympy (the
window's picking and glyphs read them: deriving the registry would stall a frame for
seconds), and equal the registry's exact results evaluated in float64."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from explorer.lpv.twin.light_grid import DerivedConstants

ROOT = Path(__file__).resolve().parents[3]


def test_every_constant_equals_its_derivation():
    from derivations.registry import get

    constants = DerivedConstants()
    for name, derivation in DerivedConstants.DERIVATIONS.items():
        assert getattr(constants, name) == float(get(derivation).expr.evalf(30)), name


def test_reading_the_constants_runs_no_sympy():
    script = ("import sys\n"
              "from explorer.lpv.twin.light_grid import K, DerivedConstants\n"
              "values = [getattr(K, name) for name in DerivedConstants.DERIVATIONS]\n"
              "assert 'sympy' not in sys.modules, 'sympy was imported'\n"
              "print(len(values))\n")
    proc = subprocess.run([sys.executable, "-c", script], cwd=ROOT, capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == str(len(DerivedConstants.DERIVATIONS))
