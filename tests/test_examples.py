"""Every script in examples/ runs at its small size and saves its figure; the README links each with its figure.

Each runs as a subprocess (as a user runs it: `python examples/NAME.py --size small --out DIR`)
in a temporary directory, with this checkout on PYTHONPATH; it must exit 0 and write
DIR/NAME.png. The committed figure examples/figures/NAME.png (made at the full size) and
the README's links to the script and the figure must exist.
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
EXAMPLES = sorted(p for p in (ROOT / "examples").glob("*.py") if not p.name.startswith("_"))


def test_there_are_five_to_eight_examples():
    assert 5 <= len(EXAMPLES) <= 8, [p.name for p in EXAMPLES]


@pytest.mark.parametrize("script", EXAMPLES, ids=lambda p: p.stem)
def test_example_runs_small_and_saves_its_figure(script, tmp_path):
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]),
           "MPLBACKEND": "Agg"}
    done = subprocess.run([sys.executable, str(script), "--size", "small", "--out", str(tmp_path / "out")],
                          cwd=tmp_path, env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    figure = tmp_path / "out" / f"{script.stem}.png"
    assert figure.is_file() and figure.stat().st_size > 10_000, done.stdout[-2000:]


@pytest.mark.parametrize("script", EXAMPLES, ids=lambda p: p.stem)
def test_readme_links_the_example_and_its_figure(script):
    readme = (ROOT / "README.md").read_text()
    assert (ROOT / "examples" / "figures" / f"{script.stem}.png").is_file()
    assert f"(examples/{script.name})" in readme and f"(examples/figures/{script.stem}.png)" in readme
