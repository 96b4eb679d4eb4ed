"""Maps cut from maps (Map.submap), made from arrays (Map.from_arrays), and
layers by name (map["elevation"])."""
import numpy as np
import pytest

import stridemap


def same_layer(a, b):
    np.testing.assert_array_equal(a, b)


# --- map[name] ---

def test_indexing_by_name_is_the_layer(mapped_flat_walk):
    m = mapped_flat_walk.map
    for name in m.layer_names:
        same_layer(m[name], m.layer(name))
        assert m[name].dtype == m.layer(name).dtype
    assert "elevation" in m and "foothold_score" in m.layer_names and "foothold_score" in m
    assert "no_such_layer" not in m and 3 not in m


def test_an_unknown_name_is_a_key_error_listing_the_layers():
    m = stridemap.Map(4, 0.1)
    with pytest.raises(KeyError) as error:
        m["elevatoin"]
    message = str(error.value)
    assert "'elevatoin' is not a layer of this map" in message
    for name in m.layer_names:
        assert name in message


def test_cells_are_indexed_on_the_layer_not_the_map():
    m = stridemap.Map(4, 0.1)
    with pytest.raises(TypeError, match=r"expected a layer name \(str\), got int; index the layer"):
        m[0]
    with pytest.raises(TypeError, match=r"got tuple"):
        m[1, 2]
    with pytest.raises(TypeError, match="not iterable"):
        iter(m)


# --- Map.submap ---

def test_a_submap_holds_the_box_cells_with_their_geometry(mapped_flat_walk):
    m = mapped_flat_walk.map
    i0, j0 = np.argwhere(m["state"] == 1)[0]               # a box with mapped cells in it
    i0, j0 = min(i0, 70), min(j0, 70)
    x0, y0 = m.extent_m[0] + i0 * 0.01, m.extent_m[1] + j0 * 0.01
    sub = m.submap(x0, y0, x0 + 0.25, y0 + 0.25)          # 25 x 25 cells of 10 mm
    assert sub.cells_per_side == 25 and sub.cell_size_m == m.cell_size_m
    assert sub.min_cell == (m.min_cell[0] + i0, m.min_cell[1] + j0)
    assert sub.extent_m == pytest.approx((x0, y0, x0 + 0.25, y0 + 0.25))
    np.testing.assert_array_equal(sub.x_m(), m.x_m()[i0:i0 + 25])
    np.testing.assert_array_equal(sub.y_m(), m.y_m()[j0:j0 + 25])
    cells = np.array([[sub.min_cell[0], sub.min_cell[1]], [sub.min_cell[0] + 24, sub.min_cell[1] + 3]])
    np.testing.assert_array_equal(sub.centers_of(cells), m.centers_of(cells))
    assert sub.layer_names == m.layer_names                 # the foothold layers too
    for name in m.layer_names:
        same_layer(sub[name], m[name][i0:i0 + 25, j0:j0 + 25])
    assert np.count_nonzero(sub["state"] == 1) > 0          # the box holds mapped cells


def test_a_whole_map_box_is_a_copy(mapped_flat_walk):
    m = mapped_flat_walk.map
    sub = m.submap(*m.extent_m)
    assert sub.min_cell == m.min_cell and sub.cells_per_side == m.cells_per_side
    for name in m.layer_names:
        same_layer(sub[name], m[name])


def test_a_box_that_is_not_square_is_padded_with_unknown_cells():
    e = np.arange(100, dtype=float).reshape(10, 10) / 100.0
    m = stridemap.Map.from_arrays(e, np.ones((10, 10)), cell_size_m=0.1, corner_m=(0.0, 0.0))
    sub = m.submap(0.2, 0.1, 0.5, 0.8)                      # 3 x 7 cells
    assert sub.cells_per_side == 7 and sub.min_cell == (2, 1)
    same_layer(sub["elevation"][:3, :7], m["elevation"][2:5, 1:8])
    assert np.all(np.isnan(sub["elevation"][3:, :])) and np.all(sub["state"][3:, :] == 0)
    assert np.all(sub["certainty"][3:, :] == 0)


def test_box_edges_on_cell_edges_and_inside_cells():
    m = stridemap.Map.from_arrays(np.zeros((10, 10)), np.ones((10, 10)), cell_size_m=0.1, corner_m=(0.0, 0.0))
    assert m.submap(0.3, 0.3, 0.6, 0.6).cells_per_side == 3      # 0.3 / 0.1 is 2.9999999999999996
    assert m.submap(0.25, 0.25, 0.55, 0.55).min_cell == (2, 2)
    assert m.submap(0.25, 0.25, 0.55, 0.55).cells_per_side == 4  # cells 2..5 overlap it
    one = m.submap(0.42, 0.57, 0.42, 0.57)                        # zero width: the cell holding it
    assert one.cells_per_side == 1 and one.min_cell == (4, 5)


def test_a_box_partly_outside_is_clipped():
    m = stridemap.Map.from_arrays(np.zeros((10, 10)), np.ones((10, 10)), cell_size_m=0.1, corner_m=(0.0, 0.0))
    sub = m.submap(-5.0, 0.8, 0.2, 1e300)
    assert sub.min_cell == (0, 8) and sub.cells_per_side == 2
    assert np.all(sub["state"][:2, :2] == 1)


@pytest.mark.parametrize("box, message", [
    ((float("nan"), 0.0, 1.0, 1.0), r"^min_x_m: expected a finite number, got nan"),
    ((0.0, 0.0, 1.0, float("inf")), r"^max_y_m: expected a finite number, got inf"),
    ((0.5, 0.0, 0.2, 1.0), r"^min_x_m: 0\.5 m is greater than max_x_m 0\.2 m"),
    ((0.0, 0.9, 1.0, 0.1), r"^min_y_m: 0\.9 m is greater than max_y_m 0\.1 m"),
    ((2.0, 2.0, 3.0, 3.0), r"^box \(min_x_m=2, min_y_m=2, max_x_m=3, max_y_m=3\) holds no cell of the map, "
                           r"whose extent_m is \(0, 0, 1, 1\)"),
    ((1.0, 0.0, 2.0, 1.0), r"^box \(min_x_m=1, .* holds no cell"),   # touching the edge only
])
def test_bad_boxes_are_value_errors_naming_the_argument(box, message):
    m = stridemap.Map.from_arrays(np.zeros((10, 10)), np.ones((10, 10)), cell_size_m=0.1, corner_m=(0.0, 0.0))
    with pytest.raises(ValueError, match=message):
        m.submap(*box)


# --- Map.from_arrays ---

def small_arrays():
    elevation = np.full((5, 5), np.nan)
    certainty = np.zeros((5, 5))
    elevation[1, 2], certainty[1, 2] = 0.25, 3.0    # measured
    elevation[4, 0], certainty[4, 0] = -0.125, 0.5  # measured
    elevation[3, 3] = 0.5                            # filled: an elevation without certainty
    return elevation, certainty


def test_from_arrays_places_the_cells_and_derives_the_state():
    elevation, certainty = small_arrays()
    m = stridemap.Map.from_arrays(elevation, certainty, cell_size_m=0.02, corner_m=(1.0, -0.5))
    assert m.cells_per_side == 5 and m.cell_size_m == 0.02
    assert m.min_cell == (50, -25) and m.extent_m == pytest.approx((1.0, -0.5, 1.1, -0.4))
    assert m["elevation"].dtype == np.float32
    same_layer(m["elevation"], elevation.astype(np.float32))
    same_layer(m["certainty"], certainty.astype(np.float32))
    expected_state = np.zeros((5, 5), np.uint8)
    expected_state[1, 2] = expected_state[4, 0] = 1
    expected_state[3, 3] = 2
    same_layer(m["state"], expected_state)
    # Element [i, j] is cell min_cell + (i, j): x along axis 0.
    assert m.cell_of(1.0 + 1.5 * 0.02, -0.5 + 2.5 * 0.02) == (m.min_cell[0] + 1, m.min_cell[1] + 2)
    # A measured cell's running mean starts from its elevation.
    assert m["mean_elevation"][1, 2] == np.float32(0.25) and m["mean_count"][1, 2] == 1
    assert m["mean_count"][3, 3] == 0


def test_from_arrays_centres_the_window_by_default():
    m = stridemap.Map.from_arrays(np.zeros((4, 4)), np.ones((4, 4)), cell_size_m=0.5)
    assert m.min_cell == stridemap.Map(4, 0.5).min_cell


def test_from_arrays_round_trips_through_a_map_file(tmp_path):
    elevation, certainty = small_arrays()
    flags = np.arange(25, dtype=np.uint8).reshape(5, 5)
    m = stridemap.Map.from_arrays(elevation, certainty, cell_size_m=0.02, corner_m=(1.0, -0.5),
                                  layers={"flags": flags, "roughness": np.full((5, 5), 0.125),
                                          "contradictions": np.ones((5, 5), int)})
    assert m["flags"].dtype == np.uint8 and m["roughness"].dtype == np.float32
    m.save(tmp_path / "arrays.smap")
    loaded = stridemap.load_map(tmp_path / "arrays.smap").map
    assert loaded.min_cell == m.min_cell and loaded.cell_size_m == m.cell_size_m
    assert loaded.layer_names == m.layer_names
    for name in m.layer_names:
        same_layer(loaded[name], m[name])
    same_layer(loaded["elevation"], elevation.astype(np.float32))
    same_layer(loaded["flags"], flags)


def test_from_arrays_of_a_mapped_map_gives_the_same_map(mapped_flat_walk, tmp_path):
    m = mapped_flat_walk.map
    again = stridemap.Map.from_arrays(m["elevation"], m["certainty"], cell_size_m=m.cell_size_m,
                                      corner_m=m.extent_m[:2], state=m["state"])
    assert again.min_cell == m.min_cell
    for name in ("elevation", "certainty", "state"):
        same_layer(again[name], m[name])


def test_a_given_state_is_kept_when_it_agrees():
    elevation, certainty = small_arrays()
    state = np.zeros((5, 5), np.uint8)
    state[1, 2] = state[4, 0] = 1
    state[3, 3] = 2
    m = stridemap.Map.from_arrays(elevation, certainty, cell_size_m=0.02, state=state)
    same_layer(m["state"], state)


def expect_error(message, error=stridemap.InputError, **changes):
    elevation, certainty = small_arrays()
    arguments = dict(elevation_m=elevation, certainty=certainty, cell_size_m=0.02)
    arguments.update(changes)
    with pytest.raises(error, match=message):
        stridemap.Map.from_arrays(arguments.pop("elevation_m"), arguments.pop("certainty"), **arguments)


def test_from_arrays_shapes_and_types():
    expect_error(r"^elevation_m: expected a square array \(N, N\) .* got shape \(3, 4\)", elevation_m=np.zeros((3, 4)))
    expect_error(r"^elevation_m: expected a square array .* got shape \(5,\)", elevation_m=np.zeros(5))
    expect_error(r"^elevation_m: expected a square array .* got shape \(0, 0\)", elevation_m=np.zeros((0, 0)))
    expect_error(r"^certainty: expected shape \(5, 5\) like elevation_m, got \(4, 4\)", certainty=np.zeros((4, 4)))
    expect_error(r"^state: expected shape \(5, 5\) like elevation_m, got \(5,\)", state=np.zeros(5))
    expect_error(r"^layers\['roughness'\]: expected shape \(5, 5\)", layers={"roughness": np.zeros((2, 2))})
    expect_error(r"^elevation_m: expected an array of numbers, got dtype bool", TypeError,
                 elevation_m=np.zeros((5, 5), bool))
    expect_error(r"^certainty: expected an array of numbers", TypeError, certainty=[["a"] * 5] * 5)
    expect_error(r"^layers: expected a dict", TypeError, layers=[np.zeros((5, 5))])
    expect_error(r"^elevation_m: 5000 x 5000 cells; a Map holds at most 4096", stridemap.GridSizeError,
                 elevation_m=np.broadcast_to(np.float64(0.0), (5000, 5000)))


def test_from_arrays_geometry():
    expect_error(r"^cell_size_m: expected 0\.0001 to 10 m, got 0", stridemap.GridSizeError, cell_size_m=0.0)
    expect_error(r"^cell_size_m: .* got nan", stridemap.GridSizeError, cell_size_m=float("nan"))
    expect_error(r"^corner_m\[0\]: 0\.005 m is not on the grid of 0\.02 m cells .* the nearest is 0 m",
                 corner_m=(0.005, 0.0))
    expect_error(r"^corner_m\[1\]: expected a finite number, got nan", corner_m=(0.0, float("nan")))
    expect_error(r"^corner_m: expected 2 numbers \(min_x_m, min_y_m\), got shape \(3,\)", corner_m=(0.0, 0.0, 0.0))
    expect_error(r"^corner_m\[0\]: 1e\+300 m is beyond the cell grid", corner_m=(1e300, 0.0))


def test_from_arrays_values_follow_the_map_file_rules():
    elevation, certainty = small_arrays()
    e = elevation.copy()
    e[2, 1] = np.inf
    expect_error(r"^elevation_m\[2, 1\]: expected a finite number or NaN, got inf", elevation_m=e)
    e[2, 1] = 1e39
    expect_error(r"^elevation_m\[2, 1\]: 1e\+39 does not fit float32", elevation_m=e)
    for bad, text in ((np.nan, "nan"), (np.inf, "inf"), (-1.0, "-1")):
        c = certainty.copy()
        c[0, 4] = bad
        expect_error(rf"^certainty\[0, 4\]: expected a (finite number|number >= 0), got {text}", certainty=c)
    c = certainty.copy()
    c[0, 0] = 2.0  # elevation NaN there
    expect_error(r"^elevation_m\[0, 0\]: NaN \(unknown\) where certainty\[0, 0\] is 2 > 0", certainty=c)
    state = np.zeros((5, 5))
    state[1, 2] = state[4, 0] = 1
    state[3, 3] = 2
    s = state.copy()
    s[1, 2] = 2
    expect_error(r"^state\[1, 2\] is 2 \(filled\) but certainty\[1, 2\] is 3, not 0", state=s)
    s = state.copy()
    s[3, 3] = 0
    expect_error(r"^state\[3, 3\] is 0 \(unknown\) but elevation_m\[3, 3\] is 0\.5, not NaN", state=s)
    s = state.copy()
    s[0, 1] = 3
    expect_error(r"^state\[0, 1\]: expected a whole number from 0 to 2, got 3", state=s)
    expect_error(r"^layers\['elevation'\]: pass it as elevation_m", layers={"elevation": elevation})
    expect_error(r"^layers\['mean_count'\]\[0, 0\]: expected a whole number from 0 to 65535, got -1",
                 layers={"mean_count": np.full((5, 5), -1)})
    expect_error(r"^layers\['Bad Name'\]: .*", layers={"Bad Name": np.zeros((5, 5))})
    expect_error(r"^layers\['mean_elevation'\]\[0, 0\]: expected a finite number or NaN, got inf",
                 layers={"mean_elevation": np.full((5, 5), np.inf)})


def test_mapping_goes_on_from_a_map_made_from_arrays(flat_walk):
    from conftest import FLOOR_M
    n = 100
    elevation = np.full((n, n), FLOOR_M)
    m = stridemap.Map.from_arrays(elevation, np.full((n, n), 3.0), cell_size_m=0.01)
    pipeline = stridemap.Pipeline(stridemap.PipelineOptions(follow_robot=False), resume_from=m)
    pipeline.add_urg_scans(flat_walk["ranges_mm"], flat_walk["times_s"], flat_walk["poses"],
                           reference_elevation_m=flat_walk["reference_elevation_m"],
                           height_change_m=flat_walk["height_change_m"])
    after = pipeline.map
    counts = after["mean_count"]
    assert counts.max() > 1                                  # scans added readings to the cells
    measured = after["state"] == 1
    assert np.all(np.isfinite(after["mean_elevation"][measured]))
    np.testing.assert_allclose(after["mean_elevation"][counts > 1], FLOOR_M, atol=0.03)
