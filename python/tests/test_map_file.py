"""The map file (.smap) and the exports from Python."""
import json
import os
import subprocess

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
    for name in m.layer_names:
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
    assert sorted(os.path.basename(p) for p in written) == sorted(name + ".npy" for name in m.layer_names)
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


METADATA_KEYS = {"tool_version", "created_by", "config_text", "mount", "last_scan_time_s", "last_pose"}


def file_header(path):
    """The map file's metadata JSON as written (docs/map_file.md)."""
    with open(path, "rb") as f:
        data = f.read()
    length = int.from_bytes(data[12:16], "little")
    return json.loads(data[16:16 + length])


def test_layer_names_are_the_maps_own_registry(mapped_flat_walk):
    bare = stridemap.Map(10, 0.01)
    assert bare.layer_names == ("elevation", "certainty", "mean_elevation", "pending_elevation", "mean_count",
                                "state", "contradictions")
    walked = mapped_flat_walk.map
    # The pipeline's foothold layers come after the built-in ones: 12, not 7.
    assert walked.layer_names[:7] == bare.layer_names
    assert "foothold_score" in walked.layer_names and len(walked.layer_names) == 12
    assert walked.layer_names == tuple(walked.layers())
    bare.add_layer("hits", dtype="uint16")
    assert bare.layer_names[-1] == "hits"


def test_a_pipelines_map_records_what_the_cli_records(tmp_path, flat_walk, mapped_flat_walk):
    pipeline = mapped_flat_walk
    options = pipeline.options
    from_map, from_pipeline = str(tmp_path / "map.smap"), str(tmp_path / "pipeline.smap")
    pipeline.map.save(from_map)
    pipeline.save(from_pipeline)
    with open(from_map, "rb") as a, open(from_pipeline, "rb") as b:
        assert a.read() == b.read()

    metadata = stridemap.load_map(from_map).metadata
    assert set(metadata) == METADATA_KEYS
    assert metadata["created_by"] == "Python stridemap.Pipeline"
    assert metadata["mount"].height_m == options.mount.height_m
    assert metadata["mount"].pitch_rad == options.mount.pitch_rad
    config = json.loads(metadata["config_text"])
    assert set(config) == {"mount", "map", "update", "fill", "range_calibration", "foothold", "height_fusion"}
    assert config["map"]["cells_per_side"] == options.cells_per_side
    assert config["map"]["cell_size_m"] == options.cell_size_m
    assert config["update"]["elevation_rule"] == options.update.elevation_rule
    assert config["mount"]["height_m"] == options.mount.height_m
    last = len(flat_walk["times_s"]) - 1
    assert metadata["last_scan_time_s"] == pipeline.last_scan_time_s == flat_walk["times_s"][last]
    pose = metadata["last_pose"]
    assert (pose["x_m"], pose["y_m"], pose["yaw_rad"]) == (flat_walk["poses"][last][0], flat_walk["poses"][last][1],
                                                           flat_walk["poses"][last][4])
    assert pose["reference_elevation_m"] == flat_walk["reference_elevation_m"][last]
    assert pose["z_m"] is None

    header = file_header(from_map)
    assert header["mount"] and header["config"] and header["last_pose"]
    assert header["geometry"]["cell_size_m"] == options.cell_size_m
    assert [layer["name"] for layer in header["layers"]] and len(header["layers"]) == len(pipeline.map.layer_names)
    assert all("units" in layer and "meaning" in layer for layer in header["layers"])


def test_the_configuration_is_the_pipelines_own(tmp_path):
    options = stridemap.PipelineOptions()
    options.cell_size_m = 0.02
    options.mount = stridemap.SensorMount(height_m=0.4)
    pipeline = stridemap.Pipeline(options)
    path = str(tmp_path / "coarse.smap")
    pipeline.save(path, created_by="my script")
    metadata = stridemap.load_map(path).metadata
    config = json.loads(metadata["config_text"])
    assert config["map"]["cell_size_m"] == 0.02 and config["mount"]["height_m"] == 0.4
    assert metadata["created_by"] == "my script"
    # Nothing mapped yet: no last scan to record.
    assert metadata["last_pose"] is None and metadata["last_scan_time_s"] is None


def test_a_map_of_its_own_records_only_what_is_given(tmp_path, mapped_flat_walk):
    copy_path = str(tmp_path / "copy.smap")
    mapped_flat_walk.map.copy().save(copy_path)
    bare = stridemap.load_map(copy_path).metadata
    assert bare["mount"] is None and bare["config_text"] == "" and bare["last_pose"] is None

    # A loaded file's metadata hands back to save unchanged.
    mapped_flat_walk.save(str(tmp_path / "walk.smap"))
    recorded = stridemap.load_map(str(tmp_path / "walk.smap")).metadata
    again = str(tmp_path / "again.smap")
    stridemap.Map(10, 0.01).save(again, **{k: v for k, v in recorded.items() if k != "tool_version"})
    copied = stridemap.load_map(again).metadata
    assert copied["config_text"] == recorded["config_text"]
    assert copied["last_pose"] == recorded["last_pose"]
    assert copied["mount"].height_m == recorded["mount"].height_m

    # Given arguments replace the pipeline's.
    mapped_flat_walk.map.save(again, created_by="me", last_scan_time_s=99.0)
    replaced = stridemap.load_map(again).metadata
    assert replaced["created_by"] == "me" and replaced["last_scan_time_s"] == 99.0
    assert replaced["config_text"] == recorded["config_text"]

    pose = dict(recorded["last_pose"])
    del pose["yaw_rad"]
    with pytest.raises(stridemap.InputError, match="last_pose: 'yaw_rad' is missing"):
        stridemap.Map(10, 0.01).save(again, last_pose=pose)
    pose["yaw_rad"] = "0.1"
    with pytest.raises(TypeError, match="last_pose.yaw_rad: expected a number, got str"):
        stridemap.Map(10, 0.01).save(again, last_pose=pose)
    pose["yaw_rad"] = float("nan")
    with pytest.raises(stridemap.InputError, match="last_pose.yaw_rad"):
        stridemap.Map(10, 0.01).save(again, last_pose=pose)


CLI = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(stridemap.__file__)))), "bin",
                   "stridemap")


@pytest.mark.skipif(not os.access(CLI, os.X_OK), reason="the stridemap command is not built beside the module")
def test_the_cli_resumes_a_pipelines_map_and_refuses_a_bare_one(tmp_path, flat_walk, mapped_flat_walk):
    mapped_flat_walk.map.save(str(tmp_path / "python.smap"))
    mapped_flat_walk.map.copy().save(str(tmp_path / "bare.smap"))
    # Three of the walk's scans again, later, through `import` (ranges in
    # metres at the URG-04LX's own angles, poses as a TUM trajectory).
    times = [10.0, 10.1, 10.2]
    with open(tmp_path / "ranges.csv", "w") as f:
        for t, k in zip(times, (20, 21, 22)):
            f.write(f"{t}," + ",".join(f"{v / 1000.0:.3f}" for v in flat_walk["ranges_mm"][k]) + "\n")
    with open(tmp_path / "traj.txt", "w") as f:
        for t in (9.9, 10.0, 10.1, 10.2, 10.3):
            f.write(f"{t} 0.3 0.0 0.0 0 0 0 1\n")

    def cli(*args):
        return subprocess.run([CLI, *args], cwd=tmp_path, capture_output=True, text=True, timeout=120)

    assert cli("import", "csv-ranges", "ranges.csv", "--log", "ranges.log").returncode == 0
    assert cli("import", "tum", "traj.txt", "--poses", "traj.poses").returncode == 0
    resumed = cli("map", "--log", "ranges.log", "--poses", "traj.poses", "--resume", "python.smap", "--out", "out")
    assert resumed.returncode == 0, resumed.stderr
    refused = cli("map", "--log", "ranges.log", "--poses", "traj.poses", "--resume", "bare.smap", "--out", "bare")
    assert refused.returncode == 2, refused.stderr
    assert "--resume bare.smap: cannot resume mapping from this map: the file does not record the sensor mount " \
           "or the mapper configuration" in refused.stderr
    assert not (tmp_path / "bare").exists()
