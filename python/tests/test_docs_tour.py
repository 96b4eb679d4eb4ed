"""docs/python.md's tour runs as written, on a simulated walk: the code is
read from the page, so a call the page shows that no longer works fails
here."""
import os
import re

import numpy as np
import pytest

from conftest import SOURCE_DIR


def tour_code():
    with open(os.path.join(SOURCE_DIR, "docs", "python.md"), encoding="utf-8") as page:
        text = page.read()
    tour = text.split("## A tour", 1)[1]
    match = re.search(r"```python\n(.*?)```", tour, re.S)
    assert match, "docs/python.md has no code block under 'A tour'"
    return match.group(1)


def test_the_tour_runs_on_a_walk(flat_walk, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    ranges_mm = np.asarray(flat_walk["ranges_mm"])
    poses_all = np.asarray(flat_walk["poses"])
    # The names the tour leaves to the reader: one scan in mm, one in
    # metres, then the rest of the walk, on times after the first two.
    names = {
        "raw_mm": ranges_mm[0],
        "x": poses_all[0][0], "y": poses_all[0][1], "roll": poses_all[0][2],
        "pitch": poses_all[0][3], "yaw": poses_all[0][4],
        "ranges_m": ranges_mm[1] / 1000.0,
        "pose": poses_all[1],
        "ranges": ranges_mm[2:],
        "times_s": np.asarray(flat_walk["times_s"])[2:] - flat_walk["times_s"][2] + 13.0,
        "poses": poses_all[2:],
        "heights_m": np.zeros((50, 50), dtype=np.float32),
        "certainty": np.ones((50, 50), dtype=np.float32),
    }
    exec(compile(tour_code(), "docs/python.md (A tour)", "exec"), names)
    assert names["mapped"] == len(ranges_mm) - 2
    assert np.isfinite(names["elevation"]).any()
    assert os.path.exists("walk.smap") and os.path.exists("map.ply")
    assert names["mine"].cell_size_m == pytest.approx(0.02)
