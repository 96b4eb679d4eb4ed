"""The map file (.smap) and the exports from Python."""
import os

import numpy as np
import pytest

import stridemap


def test_round_trip_is_bit_exact(tmp_path, mapped_flat_walk):
    m = mapped_flat_walk.map
    path = str(tmp_path / "walk.smap")
    mount = stridemap.SensorMount(height_m=0.3)
    m.save(path, created_by="pytest", config_text="{}", mount=mount, last_scan_time_s=4.0)
    assert stridemap.is_map_file(path)
    loaded = stridemap.load_map(path)
    assert loaded.version >= 1
    assert loaded.metadata["created_by"] == "pytest"
    assert loaded.metadata["mount"].height_m == 0.3
    assert loaded.metadata["last_scan_time_s"] == 4.0
    assert loaded.metadata["tool_version"].startswith("stridemap")
    lm = loaded.map
    assert lm.min_cell == m.min_cell and lm.cell_size_m == m.cell_size_m
    for name in stridemap.Map.layer_names:
        a, b = m.layer(name), lm.layer(name)
        assert a.tobytes() == b.tobytes(), name


def test_a_loaded_map_goes_on_mapping(tmp_path, flat_walk, mapped_flat_walk):
    path = str(tmp_path / "walk.smap")
    mapped_flat_walk.map.save(path)
    resumed = stridemap.Pipeline(resume_from=stridemap.load_map(path).map)
    assert np.array_equal(resumed.map.layer("elevation"), mapped_flat_walk.map.layer("elevation"), equal_nan=True)
    before = np.count_nonzero(resumed.map.layer("state"))
    k = 40
    resumed.add_urg_scan(flat_walk["ranges_mm"][k], 10.0, flat_walk["poses"][k] + [0.2, 0, 0, 0, 0],
                         reference_elevation_m=flat_walk["reference_elevation_m"][k])
    assert resumed.stats["integrated"] == 1


def test_saving_over_a_user_file_is_refused(tmp_path, mapped_flat_walk):
    path = tmp_path / "notes.txt"
    path.write_text("my notes\n")
    with pytest.raises(stridemap.InputError, match="notes.txt"):
        mapped_flat_walk.map.save(str(path))
    assert path.read_text() == "my notes\n"


def test_a_damaged_file_names_the_problem(tmp_path, mapped_flat_walk):
    path = tmp_path / "walk.smap"
    mapped_flat_walk.map.save(str(path))
    data = bytearray(path.read_bytes())
    data[len(data) // 2] ^= 0xFF
    path.write_bytes(bytes(data))
    with pytest.raises(stridemap.InputError, match="walk.smap"):
        stridemap.load_map(str(path))
    with pytest.raises(stridemap.InputError, match="missing.smap"):
        stridemap.load_map(str(tmp_path / "missing.smap"))


def test_exports_write_their_files(tmp_path, mapped_flat_walk):
    m = mapped_flat_walk.map
    written = m.export_npy(str(tmp_path / "npy"))
    # every layer of this map: the built-in ones and the pipeline's foothold layers
    assert len(written) == len(m.layers())
    assert len(written) > len(stridemap.Map.layer_names)
    elevation = np.load(str(tmp_path / "npy" / "elevation.npy"))
    assert np.array_equal(elevation, m.layer("elevation"), equal_nan=True)
    ply = m.export_ply(str(tmp_path / "map.ply"))
    assert ply["vertices"] == np.count_nonzero(m.layer("state"))
    assert os.path.exists(m.export_csv(str(tmp_path / "csv")))
    m.write_pictures(str(tmp_path / "pictures"))
    assert (tmp_path / "pictures" / "elevation.png").read_bytes()[:4] == b"\x89PNG"


def test_write_png_checks_its_array(tmp_path):
    stridemap.write_png(str(tmp_path / "a.png"), np.zeros((4, 5, 3), np.uint8))
    assert (tmp_path / "a.png").read_bytes()[:4] == b"\x89PNG"
    with pytest.raises(TypeError, match="pixels"):
        stridemap.write_png(str(tmp_path / "b.png"), np.zeros((4, 5, 3)))
    with pytest.raises(stridemap.InputError, match="pixels"):
        stridemap.write_png(str(tmp_path / "b.png"), np.zeros((4, 5), np.uint8))


def test_a_layer_of_your_own_is_saved_and_loaded_by_name(tmp_path):
    m = stridemap.Map(20, 0.05)
    m.add_layer("hit_count", dtype="uint16", description="points per cell")
    assert "hit_count" in m.layers()
    view = m.layer("hit_count")
    assert view.dtype == np.uint16 and view.shape == (20, 20) and not view.any()
    path = str(tmp_path / "own.smap")
    m.save(path)
    loaded = stridemap.load_map(path).map
    assert loaded.layer("hit_count").dtype == np.uint16
    assert list(loaded.layers()) == list(m.layers())
    with pytest.raises(stridemap.InputError, match="hit_count"):
        stridemap.Map(20, 0.05).layer("hit_count")  # named in the message, with the layers there are
    with pytest.raises(stridemap.InputError, match="dtype"):
        m.add_layer("other", dtype="int64")
    with pytest.raises(stridemap.InputError):
        m.add_layer("hit_count", dtype="uint16")  # declared twice
