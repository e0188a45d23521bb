"""The Python example runs and writes its figure."""

import subprocess
import sys

import matplotlib.image

from conftest import SOURCE_DIR


def test_descriptors_to_map_example(tmp_path):
    out = tmp_path / "map.png"
    script = SOURCE_DIR / "examples" / "python" / "01_descriptors_to_map.py"
    result = subprocess.run([sys.executable, str(script), str(out)], capture_output=True, text=True, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "places" in result.stdout
    image = matplotlib.image.imread(out)
    assert image.shape[0] > 100 and image.shape[1] > 100


def test_map_evaluate_report_example_prints_short_summaries(tmp_path):
    script = SOURCE_DIR / "examples" / "python" / "02_map_evaluate_report.py"
    result = subprocess.run([sys.executable, str(script), str(tmp_path)], capture_output=True, text=True, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert len(lines) == 5, result.stdout
    assert all(len(line) < 220 for line in lines), result.stdout
    assert lines[0].startswith("MapRun(") and "F1 " in lines[0], lines[0]
    assert lines[1].startswith("MapResult(84 images"), lines[1]
    assert lines[2].startswith("Alignment(forward, score"), lines[2]
    assert lines[3].startswith("LocalizeRun(second in first: 44 query frames in 40 map frames") and "recall@1" in lines[3]
    assert (tmp_path / "map" / "report.html").exists() and (tmp_path / "localize" / "report.html").exists()
