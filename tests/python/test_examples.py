"""examples/python/compare.py runs and writes its chart."""
import os
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_compare_writes_a_png(tmp_path):
    out = tmp_path / "compare.png"
    result = subprocess.run([sys.executable, str(ROOT / "examples/python/compare.py"), "--scene", "crowd",
                             "--size", "0.003", "--rays", "3000", "--repeats", "1", "--out", str(out)],
                            capture_output=True, text=True, env=dict(os.environ, MPLBACKEND="Agg"))
    assert result.returncode == 0, result.stderr
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "stbvh" in result.stdout and "mbkd" in result.stdout
