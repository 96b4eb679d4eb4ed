"""The map as NumPy users expect it: arrays of cells and centres,
coordinate axes, pickling and copying, paths as pathlib.Path, a repr."""
import copy
import pathlib
import pickle

import numpy as np
import pytest

import stridemap


def test_cells_and_centres_of_many_points_match_the_scalar_calls(mapped_flat_walk):
    m = mapped_flat_walk.map
    rng = np.random.default_rng(3)
    points = rng.uniform(-2.0, 2.0, (200, 2))
    cells = m.cells_of(points)
    assert cells.shape == (200, 2) and cells.dtype == np.int64
    for p, c in zip(points, cells):
        assert tuple(c) == m.cell_of(*p)
    centres = m.centers_of(cells)
    for c, xy in zip(cells, centres):
        assert tuple(xy) == m.cell_center(*c)
    assert np.all(np.abs(centres - points) <= m.cell_size_m / 2 + 1e-12)
    with pytest.raises(stridemap.InputError, match=r"points_m: expected shape \(N, 2\)"):
        m.cells_of(np.zeros((3, 3)))
    with pytest.raises(stridemap.InputError, match=r"points_m\[1\]\[0\].*beyond the cell grid"):
        m.cells_of([[0.0, 0.0], [1e300, 0.0]])


def test_coordinate_axes_follow_the_layer_arrays(mapped_flat_walk):
    m = mapped_flat_walk.map
    x, y = m.x_m(), m.y_m()
    assert x.shape == (m.cells_per_side,) and y.shape == (m.cells_per_side,)
    i, j = 7, 31
    assert (x[i], y[j]) == m.cell_center(m.min_cell[0] + i, m.min_cell[1] + j)
    assert x[0] - m.cell_size_m / 2 == pytest.approx(m.extent_m[0])
    assert y[-1] + m.cell_size_m / 2 == pytest.approx(m.extent_m[3])


def test_pickle_and_deepcopy_give_the_same_cells(mapped_flat_walk):
    m = mapped_flat_walk.map
    for other in (pickle.loads(pickle.dumps(m)), copy.deepcopy(m), copy.copy(m)):
        assert other.min_cell == m.min_cell and other.cell_size_m == m.cell_size_m
        assert other.layer_names == m.layer_names
        for name in m.layer_names:
            np.testing.assert_array_equal(other.layer(name), m.layer(name))


def test_paths_may_be_pathlib_paths(mapped_flat_walk, tmp_path):
    path = pathlib.Path(tmp_path) / "walk.smap"
    mapped_flat_walk.save(path)
    assert stridemap.is_map_file(path)
    loaded = stridemap.load_map(path)
    np.testing.assert_array_equal(loaded.map.layer("elevation"), mapped_flat_walk.map.layer("elevation"))
    loaded.map.export_npy(pathlib.Path(tmp_path) / "npy")
    assert (pathlib.Path(tmp_path) / "npy" / "elevation.npy").exists()
    with pytest.raises(TypeError):
        stridemap.load_map(3)


def test_repr_says_what_the_map_is():
    m = stridemap.Map(cells_per_side=20, cell_size_m=0.05)
    assert repr(m) == "<stridemap.Map 20 x 20 cells of 0.05 m, x -0.5..0.5 m, y -0.5..0.5 m, 7 layers, 0.0 % measured>" \
        or repr(m).startswith("<stridemap.Map 20 x 20 cells of 0.05 m")
    assert "measured>" in repr(m)
