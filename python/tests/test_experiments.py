"""The experiments through Python: summaries as dicts, outputs on request."""
import os

import pytest

import stridemap
from conftest import SOURCE_DIR

ROCKY = os.path.join(SOURCE_DIR, "scenes", "rocky_mockup.yaml")
RAIL = os.path.join(SOURCE_DIR, "scenes", "thin_edges.yaml")


def test_cart_rail_returns_its_summary_and_writes_outputs(tmp_path):
    out = tmp_path / "rail"
    summary = stridemap.run_cart_rail(RAIL, seed=3, out_dir=str(out))
    assert summary["experiment"] == "cart-rail" and summary["seed"] == 3
    assert (out / "summary.json").exists()
    import json
    assert json.loads((out / "summary.json").read_text()) == summary
    again = stridemap.run_cart_rail(RAIL, seed=3)
    assert again == summary


def test_cart_rail_coupling_is_the_clis():
    # With mixed pixels the receiver's coupling is on unless turned off, as
    # with `experiment cart-rail --coupling`; the ideal single ray never has it.
    on = stridemap.run_cart_rail(RAIL, seed=3, mixed_pixels=True)
    off = stridemap.run_cart_rail(RAIL, seed=3, mixed_pixels=True, coupling=False)
    assert on["coupling"] is True and off["coupling"] is False
    assert on["beam_labels"] != off["beam_labels"]
    assert stridemap.run_cart_rail(RAIL, seed=3)["coupling"] is False


def test_rocky_walk_records_the_coupling():
    assert stridemap.run_rocky_walk(ROCKY, seed=2, sweep=[])["coupling"] is False  # no mixed pixels


def test_rocky_walk_without_sweep_is_deterministic():
    summary = stridemap.run_rocky_walk(ROCKY, seed=2, sweep=[])
    assert summary["experiment"] == "rocky-walk" and summary["sensor"] == "urg" and summary["seed"] == 2
    assert summary["cells_per_side"] == 100 and summary["pose_error_sweep"] == []
    assert stridemap.run_rocky_walk(ROCKY, seed=2, sweep=[]) == summary
    assert stridemap.run_rocky_walk(ROCKY, seed=3, sweep=[]) != summary


def test_rocky_walk_defaults_are_the_clis():
    # The CLI's URG walk: h_ref from the map under the stance feet, the IMU
    # biases calibrated on a flat floor, no range calibration.
    summary = stridemap.run_rocky_walk(ROCKY, seed=2, sweep=[])
    assert summary["pose_error_options"]["reference"] == "map-footholds"
    assert "attitude_calibration" in summary and "range_calibration" not in summary
    plain = stridemap.run_rocky_walk(ROCKY, seed=2, sweep=[], reference="map", calibrate_attitude=False)
    assert plain["pose_error_options"]["reference"] == "map" and "attitude_calibration" not in plain
    calibrated = stridemap.run_rocky_walk(ROCKY, seed=2, sweep=[], calibrate_range=True)
    assert len(calibrated["range_calibration"]["coefficients"]) == 4
    assert calibrated["range_calibration"] != summary.get("range_calibration")


def test_experiment_errors_are_input_errors(tmp_path):
    with pytest.raises(stridemap.InputError, match="missing.yaml"):
        stridemap.run_cart_rail(str(tmp_path / "missing.yaml"))
    with pytest.raises(stridemap.InputError, match="'lidar'"):
        stridemap.run_cart_rail(RAIL, sensor="lidar")
    user = tmp_path / "mine"
    user.mkdir()
    (user / "thesis.tex").write_text("keep me")
    with pytest.raises(stridemap.InputError, match="out_dir"):
        stridemap.run_cart_rail(RAIL, out_dir=str(user))
    assert (user / "thesis.tex").read_text() == "keep me"
