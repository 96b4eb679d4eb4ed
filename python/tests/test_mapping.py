"""Mapping simulated scans through the pipeline, checked against the scene."""
import numpy as np
import pytest

import stridemap
from conftest import FLOOR_M, map_walk


def test_simulated_walk_has_consistent_shapes(flat_walk):
    k = flat_walk["times_s"].shape[0]
    assert k == 41  # 4 s at the URG's 0.1 s per scan, both ends included
    assert flat_walk["ranges_mm"].shape == (k, stridemap.UrgParameters().beam_count)
    assert flat_walk["ranges_mm"].dtype == np.uint32
    assert flat_walk["poses"].shape == (k, 5)
    assert np.all(np.diff(flat_walk["poses"][:, 0]) >= 0)  # walking forward along +X


def test_map_of_a_flat_floor_is_at_the_floor_height(mapped_flat_walk):
    layers = mapped_flat_walk.map.layers()
    state, elevation = layers["state"], layers["elevation"]
    measured = elevation[state == 1]
    assert measured.size > 500
    # Eq. (10) keeps the highest reading, about one noise sigma above the
    # floor; the mean of the accepted readings sits on it.
    assert abs(float(np.median(measured)) - FLOOR_M) < 0.01
    mean = layers["mean_elevation"][state == 1]
    assert abs(float(np.mean(mean)) - FLOOR_M) < 0.005
    assert np.all(np.isnan(elevation[state == 0]))
    assert np.all(layers["certainty"][state == 0] == 0)
    stats = mapped_flat_walk.stats
    assert stats["integrated"] == 41 and stats["mapper_integrated"] > 10000


def test_map_matches_the_scene_cell_by_cell(mapped_flat_walk, flat_scene):
    m = mapped_flat_walk.map
    state = m.layer("state")
    elevation = m.layer("elevation")
    i, j = np.nonzero(state == 1)
    for a, b in list(zip(i, j))[::97]:
        x, y = m.cell_center(m.min_cell[0] + int(a), m.min_cell[1] + int(b))
        assert abs(elevation[a, b] - flat_scene.surface_height_at(x, y)) < 0.02


def test_mapping_is_deterministic_for_a_seed(flat_scene, flat_walk):
    again = stridemap.simulate_walk(flat_scene, seed=7, duration_s=4.0)
    other = stridemap.simulate_walk(flat_scene, seed=8, duration_s=4.0)
    assert np.array_equal(again["ranges_mm"], flat_walk["ranges_mm"])
    assert not np.array_equal(other["ranges_mm"], flat_walk["ranges_mm"])
    a = map_walk(flat_walk).map.layer("elevation")
    b = map_walk(again).map.layer("elevation")
    assert np.array_equal(a, b, equal_nan=True)


def test_ranges_in_metres_map_like_raw_millimetres(flat_walk):
    by_mm = stridemap.Pipeline()
    by_m = stridemap.Pipeline()
    for k in range(5):
        raw = flat_walk["ranges_mm"][k]
        metres = np.where(raw < 20, np.nan, raw / 1000.0)  # error codes: no echo
        pose = flat_walk["poses"][k]
        t = flat_walk["times_s"][k]
        h = dict(reference_elevation_m=flat_walk["reference_elevation_m"][k],
                 height_change_m=flat_walk["height_change_m"][k])
        by_mm.add_urg_scan(raw, t, pose, **h)
        by_m.add_urg_scan(metres, t, pose, units="m", **h)
    assert np.array_equal(by_mm.map.layer("elevation"), by_m.map.layer("elevation"), equal_nan=True)


def test_generic_points_map_a_plane():
    options = stridemap.PipelineOptions()
    options.sensor = "points"
    options.mount = stridemap.SensorMount(height_m=0.5, pitch_rad=0.0)
    pipeline = stridemap.Pipeline(options)
    xs, ys = np.meshgrid(np.linspace(0.05, 0.4, 30), np.linspace(-0.2, 0.2, 30))
    points = np.column_stack([xs.ravel(), ys.ravel(), np.full(xs.size, -0.45)])  # 5 cm above the origin
    outcome = pipeline.add_points(points, 0.002, 1.0, [0, 0, 0, 0, 0])
    assert outcome["integrated"] == points.shape[0]
    elevation = pipeline.map.layer("elevation")
    assert np.nanmax(np.abs(elevation - 0.05)) < 1e-6


def test_six_dof_pose_places_the_sensor_at_z(flat_walk):
    # A level trunk at height z (6 values) puts the sensor where the paper's
    # model (5 values) puts it with that reference elevation: the first
    # readings of every cell agree. (Tilted, the 6-DoF pose also turns the
    # mount's lever arm, which the paper's model does not.)
    x, y, _, _, yaw = flat_walk["poses"][0]
    z = 0.03
    raw = flat_walk["ranges_mm"][0]
    five = stridemap.Pipeline()
    six = stridemap.Pipeline()
    five.add_urg_scan(raw, 0.0, [x, y, 0.0, 0.0, yaw], reference_elevation_m=z)
    six.add_urg_scan(raw, 0.0, [x, y, z, 0.0, 0.0, yaw])
    a, b = five.map.layer("elevation"), six.map.layer("elevation")
    assert np.array_equal(np.isnan(a), np.isnan(b)) and np.count_nonzero(~np.isnan(a)) > 100
    assert np.nanmax(np.abs(a - b)) < 1e-5


def test_filtered_map_fills_without_touching_the_map(mapped_flat_walk):
    before = mapped_flat_walk.map.layer("state").copy()
    filtered = mapped_flat_walk.filtered_map()
    assert np.array_equal(mapped_flat_walk.map.layer("state"), before)
    assert np.count_nonzero(filtered.layer("state") == 2) > 0
    assert mapped_flat_walk.apply_map_filter()["filled"] == np.count_nonzero(filtered.layer("state") == 2)


def test_options_from_the_cli_config_file():
    import os
    from conftest import SOURCE_DIR
    options = stridemap.PipelineOptions.from_config(os.path.join(SOURCE_DIR, "configs", "urg_messor.yaml"))
    assert options.sensor == "urg"
    assert options.cell_size_m > 0 and options.mount.height_m > 0
    stridemap.Pipeline(options)


def test_structured_light_stripes_go_through_the_pipeline():
    import os
    from conftest import SOURCE_DIR
    options = stridemap.PipelineOptions()
    options.sensor = "structured-light"
    options.load_structured_light_config(os.path.join(SOURCE_DIR, "configs", "ragno_structured_light.yaml"))
    options.map_filter = "cas"
    options.cell_size_m = 0.005
    options.cells_per_side = 200
    pipeline = stridemap.Pipeline(options)
    # One stripe across the image, a few rows apart: every pixel is looked at.
    u = np.arange(0.0, 640.0, 8.0)
    pixels = np.column_stack([u, np.full(u.size, 300.0)])
    outcome = pipeline.add_stripe(pixels, 0.5, [0, 0, 0, 0, 0])
    stats = pipeline.stats
    assert stats["stripe_pixels"] == u.size
    assert outcome["integrated"] == stats["stripe_converted"] > 0
    with pytest.raises(stridemap.InputError, match=r"pixels: expected shape \(N, 2\)"):
        pipeline.add_stripe(np.zeros((3, 3)), 0.6, [0, 0, 0, 0, 0])


def test_lazy_foothold_layers_read_as_those_updated_every_scan(flat_walk, tmp_path):
    eager_options = stridemap.PipelineOptions()
    eager_options.foothold_update_every_scan = True
    assert not stridemap.PipelineOptions().foothold_update_every_scan  # lazy is the default
    eager = stridemap.Pipeline(eager_options)
    lazy = stridemap.Pipeline()
    held = lazy.map.layer("foothold_score")  # a view, held across scans
    n = len(flat_walk["times_s"])
    for k in range(n):
        args = (flat_walk["ranges_mm"][k], flat_walk["times_s"][k], flat_walk["poses"][k])
        h = dict(reference_elevation_m=flat_walk["reference_elevation_m"][k],
                 height_change_m=flat_walk["height_change_m"][k])
        eager.add_urg_scan(*args, **h)
        lazy.add_urg_scan(*args, **h)
        if k % 10 != 9 and k != n - 1:
            continue
        a, b = eager.map.layers(), lazy.map.layers()
        assert a.keys() == b.keys()
        for name in a:
            assert np.array_equal(a[name], b[name], equal_nan=True), (k, name)
    # A view shows the layers as of the last read of the map (here: above).
    if not held.flags.writeable:
        assert np.isfinite(held).any()
        assert np.array_equal(held, eager.map.storage_view("foothold_score"), equal_nan=True)
    eager.save(str(tmp_path / "eager.smap"))
    lazy.save(str(tmp_path / "lazy.smap"))
    assert (tmp_path / "eager.smap").read_bytes() == (tmp_path / "lazy.smap").read_bytes()
