"""The README's Python snippets run verbatim (from the repository's root, as the README says),
and so does the example script."""
import os
import re
import subprocess
import sys

import pytest

SOURCE = os.path.abspath(os.environ.get("EXOID_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..")))


def readme_python_blocks():
    with open(os.path.join(SOURCE, "README.md")) as f:
        return re.findall(r"```python\n(.*?)```", f.read(), flags=re.S)


def run(code_or_path, cwd, *args):
    import exoid
    cmd = [sys.executable, *([code_or_path] if os.path.isfile(code_or_path) else ["-c", code_or_path]), *args]
    env = os.environ.copy()  # the module this test imported, wherever the child runs
    env["PYTHONPATH"] = os.pathsep.join([os.path.dirname(exoid.__file__), env.get("PYTHONPATH", "")])
    done = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    return done.stdout


def test_the_readme_has_python_snippets():
    assert len(readme_python_blocks()) >= 2


@pytest.mark.parametrize("index", range(len(readme_python_blocks())))
def test_readme_snippet_runs(index):
    import exoid
    block = readme_python_blocks()[index]
    if "exoid.simulate" in block and not exoid.has_simulator:
        pytest.skip("built without MuJoCo")
    out = run(block, SOURCE)
    assert out.strip(), "the snippet printed nothing"


def test_example_script_identifies_the_shipped_log_and_plots(tmp_path):
    png = tmp_path / "fit.png"
    out = run(os.path.join(SOURCE, "examples", "identify_real_log.py"), tmp_path, str(png))
    assert "converged" in out and png.stat().st_size > 10000
