"""The scan filters and export formats come from the library's registries."""
import os

import pytest

import stridemap


def test_scan_filters_lists_the_filters_and_the_sets():
    entries = stridemap.scan_filters()
    names = [e["name"] for e in entries]
    assert names[:5] == ["range-clustering", "scan-sequence", "shadow", "speckle", "between-scans"]
    assert all(e["description"] for e in entries)
    sets = {e["name"]: e["members"] for e in entries if "members" in e}
    assert sets["paper"] == ["range-clustering", "scan-sequence"]
    assert sets["urg"] == ["range-clustering", "scan-sequence", "between-scans"]
    options = stridemap.PipelineOptions()
    for name in names:
        options.filters = name
    options.filters = "urg"
    assert options.filters == "range-clustering,scan-sequence,between-scans"
    assert "between-scans" in stridemap.PipelineOptions.filters.__doc__


def test_export_writes_each_listed_format(tmp_path, mapped_flat_walk):
    m = mapped_flat_walk.map
    formats = {f["name"]: f for f in stridemap.export_formats()}
    assert list(formats)[:3] == ["npy", "ply", "csv"]
    assert formats["npy"]["folder"] and not formats["ply"]["folder"]
    assert formats["csv"]["takes_layers"] and not formats["ply"]["takes_layers"]
    written = m.export("npy", tmp_path / "npy", layers=["elevation", "state"])
    assert sorted(os.path.basename(p) for p in written) == ["elevation.npy", "state.npy"]
    assert all(os.path.exists(p) for p in written)
    (ply,) = m.export("ply", str(tmp_path / "map.ply"))
    m.export_ply(str(tmp_path / "direct.ply"))
    assert (tmp_path / "map.ply").read_bytes() == (tmp_path / "direct.ply").read_bytes()
    with pytest.raises(stridemap.InputError, match="npy, ply, csv"):
        m.export("obj", str(tmp_path / "map.obj"))
