"""Layers as NumPy arrays: views where the layout allows, copies otherwise."""
import gc

import numpy as np
import pytest

import stridemap


def test_storage_view_is_a_view_of_the_map_and_keeps_it_alive(mapped_flat_walk):
    m = mapped_flat_walk.map
    view = m.storage_view("elevation")
    assert view.base is not None and not view.flags.owndata
    assert not view.flags.writeable
    expected = view.copy()
    del m, mapped_flat_walk
    gc.collect()
    # The view's base holds the Map, which holds the pipeline: still valid.
    assert np.array_equal(view, expected, equal_nan=True)


def test_a_view_follows_later_scans(flat_walk):
    pipeline = stridemap.Pipeline()
    view = pipeline.map.storage_view("certainty")
    assert np.count_nonzero(view) == 0
    pipeline.add_urg_scan(flat_walk["ranges_mm"][0], 0.0, flat_walk["poses"][0],
                          reference_elevation_m=flat_walk["reference_elevation_m"][0])
    assert np.count_nonzero(view) > 0  # the same memory, now written


def test_storage_rolled_by_the_corner_is_the_window_order(mapped_flat_walk):
    m = mapped_flat_walk.map
    r, c = m.storage_corner
    assert (r, c) != (0, 0)
    for name in m.layer_names:
        window = m.layer(name)
        rolled = np.roll(m.storage_view(name), (-r, -c), (0, 1))
        assert np.array_equal(window, rolled, equal_nan=True), name
        # Not the view's memory when the corner is not in slot (0, 0).
        assert not np.shares_memory(window, m.storage_view(name))


def test_layer_is_a_view_when_the_corner_is_in_slot_zero(flat_walk):
    # The window follows the robot: centred on cell 50 of a 100-cell map,
    # its corner is cell 0, which is storage slot (0, 0).
    pipeline = stridemap.Pipeline()
    pipeline.add_urg_scan(flat_walk["ranges_mm"][0], 0.0, [0.505, 0.505, 0.0, 0.0, 0.0])
    m = pipeline.map
    assert m.min_cell == (0, 0) and m.storage_corner == (0, 0)
    layer = m.layer("elevation")
    assert np.shares_memory(layer, m.storage_view("elevation"))
    assert layer.base is not None and not layer.flags.writeable
    assert np.count_nonzero(~np.isnan(layer)) > 100


def test_layer_dtypes_and_shapes():
    m = stridemap.Map(cells_per_side=40, cell_size_m=0.02)
    dtypes = {name: m.layer(name).dtype for name in m.layer_names}
    assert dtypes == {
        "elevation": np.float32, "certainty": np.float32, "state": np.uint8, "mean_elevation": np.float32,
        "mean_count": np.uint16, "pending_elevation": np.float32, "contradictions": np.uint8,
    }
    assert all(m.layer(name).shape == (40, 40) for name in m.layer_names)


def test_views_cannot_be_written(mapped_flat_walk):
    view = mapped_flat_walk.map.storage_view("state")
    with pytest.raises(ValueError):
        view[0, 0] = 2
