"""Bad input is a Python exception naming it, with the library's words."""
import numpy as np
import pytest

import stridemap

POSE = [0.0, 0.0, 0.0, 0.0, 0.0]


def raw_scan(n=682):
    return np.full(n, 1000, dtype=np.uint32)


def test_exception_classes():
    assert issubclass(stridemap.InputError, ValueError)
    assert issubclass(stridemap.GridSizeError, stridemap.InputError)
    assert stridemap.InputError.__module__ == "stridemap"


def test_grid_size_error_carries_the_library_message():
    with pytest.raises(stridemap.GridSizeError,
                       match=r"cells_per_side must be between 1 and 4096, got 5000: 5000 x 5000 cells need"):
        stridemap.Map(cells_per_side=5000)
    options = stridemap.PipelineOptions()
    options.cell_size_m = 0.0
    with pytest.raises(stridemap.GridSizeError, match="cell_size_m must be between"):
        stridemap.Pipeline(options)


def test_option_names_are_checked():
    options = stridemap.PipelineOptions()
    with pytest.raises(stridemap.InputError, match="'lidar' is not a sensor"):
        options.sensor = "lidar"
    with pytest.raises(stridemap.InputError, match="'median' is not a map filter"):
        options.map_filter = "median"
    with pytest.raises(stridemap.InputError, match="elevation rule"):
        options.update.elevation_rule = "lowest"


def test_a_scan_too_long_for_the_sensor_is_refused_with_the_sensors_words():
    with pytest.raises(stridemap.InputError,
                       match=r"683 values with first_step 44 and cluster 1 reach step 726, beyond last_step 725"):
        stridemap.Pipeline().add_urg_scan(raw_scan(683), 0.1, POSE)


@pytest.mark.parametrize("pose, field", [
    ([0, 0, np.nan, 0, 0], "roll_rad"),
    ([0, 0, 0, 0, np.inf], "yaw_rad"),
    ([0, 0, np.nan, 0, 0, 0], "z_m"),
])
def test_non_finite_poses_name_the_field(pose, field):
    with pytest.raises(stridemap.InputError, match=f"pose: {field} is not finite"):
        stridemap.Pipeline().add_urg_scan(raw_scan(), 0.1, pose)


def test_wrong_pose_length_and_shape():
    p = stridemap.Pipeline()
    with pytest.raises(stridemap.InputError, match=r"pose: expected 5 values .* or 6 .* got 4"):
        p.add_urg_scan(raw_scan(), 0.1, [0, 0, 0, 0])
    with pytest.raises(stridemap.InputError, match="pose: expected one pose"):
        p.add_urg_scan(raw_scan(), 0.1, np.zeros((2, 5)))
    with pytest.raises(TypeError, match="pose: expected an array of numbers"):
        p.add_urg_scan(raw_scan(), 0.1, ["a", "b", "c", "d", "e"])


def test_units_are_checked_against_the_dtype_and_the_values():
    p = stridemap.Pipeline()
    with pytest.raises(TypeError, match="ranges: units='mm' takes the sensor's raw integer millimetres"):
        p.add_urg_scan(np.full(682, 1.0), 0.1, POSE)
    with pytest.raises(TypeError, match="ranges: units='m' takes floating-point metres"):
        p.add_urg_scan(raw_scan(), 0.1, POSE, units="m")
    with pytest.raises(stridemap.InputError, match=r"ranges\[0\]: 1000.000000 m is no range a URG measures"):
        p.add_urg_scan(np.full(682, 1000.0), 0.1, POSE, units="m")
    with pytest.raises(stridemap.InputError, match=r"ranges\[3\]: a range is not negative"):
        p.add_urg_scan(np.array([1.0, 1.0, 1.0, -1.0]), 0.1, POSE, units="m")
    with pytest.raises(stridemap.InputError, match=r"ranges\[1\]: a raw URG value is 0..4294967295 mm"):
        p.add_urg_scan(np.array([5, -5]), 0.1, POSE)
    with pytest.raises(stridemap.InputError, match="units: expected 'mm'"):
        p.add_urg_scan(raw_scan(), 0.1, POSE, units="cm")
    with pytest.raises(stridemap.InputError, match="ranges: expected one scan"):
        p.add_urg_scan(np.zeros((2, 682), np.uint32), 0.1, POSE)
    with pytest.raises(stridemap.InputError, match="time_s: expected a finite number"):
        p.add_urg_scan(raw_scan(), float("nan"), POSE)
    assert p.stats["scans"] == 0  # nothing reached the pipeline


def test_batches_name_the_row():
    p = stridemap.Pipeline()
    ranges = np.full((3, 682), 1000, np.uint32)
    times = np.array([0.1, 0.2, 0.3])
    poses = np.zeros((3, 5))
    poses[2, 1] = np.nan
    with pytest.raises(stridemap.InputError, match=r"poses\[2\]: y_m is not finite"):
        p.add_urg_scans(ranges, times, poses)
    with pytest.raises(stridemap.InputError, match=r"times_s: expected one time per scan \(3\)"):
        p.add_urg_scans(ranges, times[:2], np.zeros((3, 5)))
    with pytest.raises(stridemap.InputError, match=r"poses: expected shape \(3, 5\) or \(3, 6\)"):
        p.add_urg_scans(ranges, times, np.zeros((3, 4)))
    with pytest.raises(stridemap.InputError, match=r"reference_elevation_m: expected one value per scan"):
        p.add_urg_scans(ranges, times, np.zeros((3, 5)), reference_elevation_m=[0.0])


def test_points_are_checked():
    options = stridemap.PipelineOptions()
    options.sensor = "points"
    p = stridemap.Pipeline(options)
    with pytest.raises(stridemap.InputError, match=r"points: expected shape \(N, 3\)"):
        p.add_points(np.zeros((4, 2)), 0.01, 0.1, POSE)
    with pytest.raises(stridemap.InputError, match=r"sigma_m: expected one sigma per point \(4\)"):
        p.add_points(np.zeros((4, 3)), np.zeros(3), 0.1, POSE)
    with pytest.raises(stridemap.InputError, match="configured for the points sensor"):
        p.add_urg_scan(raw_scan(), 0.1, POSE)


def test_scene_and_config_errors_name_file_and_line(tmp_path):
    with pytest.raises(stridemap.InputError, match=r"bad.yaml:\d+: "):
        stridemap.parse_scene("terrain:\n  kind: flat\n  extent: 3\n", "bad.yaml")
    config = tmp_path / "c.yaml"
    config.write_text("map:\n  cell_size_m: -1\n")
    with pytest.raises(stridemap.InputError, match=r"c.yaml:2: "):
        stridemap.PipelineOptions.from_config(str(config))
    with pytest.raises(stridemap.InputError, match="no walk_path"):
        stridemap.simulate_walk(stridemap.parse_scene(
            "terrain:\n  kind: flat\n  extent: {min_x_m: 0, min_y_m: 0, max_x_m: 1, max_y_m: 1}\n"
            "  base_elevation_m: 0\n  reflectance: 0.5\n", "s.yaml"))


@pytest.mark.parametrize("x, y, field", [(1e300, 0.0, "x_m"), (0.0, -1e300, "y_m"), (4.7e16, 0.0, "x_m")])
def test_cell_of_refuses_points_beyond_the_cell_grid(x, y, field):
    m = stridemap.Map(cells_per_side=10, cell_size_m=0.01)
    with pytest.raises(stridemap.InputError, match=field + ".*beyond the cell grid"):
        m.cell_of(x, y)
    assert m.cell_of(1e6, -1e6) == (100000000, -100000000)


def test_scans_rejected_in_a_batch_are_counted_and_said():
    p = stridemap.Pipeline()
    ranges = np.full((40, 682), 1000, np.uint32)
    times = np.linspace(4.0, 0.1, 40)  # decreasing: every scan after the first is stale
    poses = np.zeros((40, 5))
    with pytest.warns(RuntimeWarning, match=r"of 40 scans were not mapped .*time not after the last mapped scan's "
                                            r"\(the first at row \d+; times_s must increase\)"):
        mapped = p.add_urg_scans(ranges, times, poses)
    p.finish()
    assert mapped <= 1
    assert p.stats["integrated"] <= 40


def test_a_clean_batch_warns_nothing():
    import warnings
    p = stridemap.Pipeline()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mapped = p.add_urg_scans(np.full((5, 682), 1000, np.uint32), np.arange(5) * 0.1 + 0.1, np.zeros((5, 5)))
    p.finish()
    assert mapped >= 4
