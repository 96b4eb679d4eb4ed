"""A walking robot's own height read where its feet stand, from the fused layers."""
import numpy as np
import pytest

import stridemap
from conftest import FLOOR_M


def fused_pipeline(walk):
    pipeline = stridemap.Pipeline(stridemap.PipelineOptions(), fused_heights=True)
    pipeline.add_urg_scans(walk["ranges_mm"], walk["times_s"], walk["poses"],
                           reference_elevation_m=walk["reference_elevation_m"],
                           height_change_m=walk["height_change_m"])
    return pipeline


def test_the_fused_layer_sits_on_the_floor_and_the_feet_give_the_trunks_height(flat_walk):
    pipeline = fused_pipeline(flat_walk)
    m = pipeline.map
    fused = m.layer("fused_elevation")
    state = m.layer("state")
    assert np.array_equal(np.isnan(fused), state == 0)
    # Eq. (10)'s highest reading sits above the floor; the fused one on it.
    assert abs(float(np.median(fused[state == 1])) - FLOOR_M) < 0.002
    assert float(np.median(m.layer("elevation")[state == 1])) > float(np.median(fused[state == 1]))

    i, j = np.nonzero(state == 1)
    middle = len(i) // 2
    cells = [(i[k], j[k]) for k in (middle - 200, middle, middle + 200)]
    feet = [(*m.cell_center(m.min_cell[0] + int(a), m.min_cell[1] + int(b)), 0.12) for a, b in cells]
    h = pipeline.stance_height(np.array(feet))
    assert h["feet_used"] == 3 and h["used"] == [True, True, True]
    assert h["trunk_z_m"] == pytest.approx(FLOOR_M + 0.12, abs=0.002)
    assert h["variance_m2"] > 0

    off_map = pipeline.stance_height(np.array([[50.0, 50.0, 0.12]]))
    assert off_map["feet_used"] == 0 and np.isnan(off_map["trunk_z_m"]) and np.isnan(off_map["ground_m"][0])


def test_stance_height_needs_the_fused_layers_and_well_formed_feet(flat_walk):
    plain = stridemap.Pipeline()
    with pytest.raises(stridemap.InputError, match="fused_heights=True"):
        plain.stance_height(np.zeros((3, 3)))
    pipeline = stridemap.Pipeline(fused_heights=True)
    with pytest.raises(stridemap.InputError, match=r"feet: expected shape \(N, 3\)"):
        pipeline.stance_height(np.zeros((3, 2)))
    with pytest.raises(stridemap.InputError, match="foot 1: depth_m: expected a finite number"):
        pipeline.stance_height(np.array([[0.0, 0.0, 0.1], [0.0, 0.0, np.nan]]))
    with pytest.raises(stridemap.InputError, match="at most 8"):
        pipeline.stance_height(np.zeros((9, 3)))
    with pytest.raises(stridemap.InputError, match="sole_radius_m"):
        pipeline.stance_height(np.zeros((1, 3)), sole_radius_m=0.0)


def test_a_configs_height_fusion_section_keeps_the_same_layers(flat_walk, tmp_path):
    config = tmp_path / "robot.yaml"
    config.write_text("height_fusion:\n  enabled: true\n")
    options = stridemap.PipelineOptions.from_config(str(config))
    from_config = stridemap.Pipeline(options)
    from_config.add_urg_scans(flat_walk["ranges_mm"], flat_walk["times_s"], flat_walk["poses"],
                              reference_elevation_m=flat_walk["reference_elevation_m"],
                              height_change_m=flat_walk["height_change_m"])
    by_keyword = fused_pipeline(flat_walk)
    assert np.array_equal(from_config.map.layer("fused_elevation"), by_keyword.map.layer("fused_elevation"),
                          equal_nan=True)
    assert "trunk_z_m" in from_config.stance_height(np.zeros((1, 3)))
    config.write_text("height_fusion:\n  mahalanobis_gate: 0\n")
    with pytest.raises(stridemap.InputError, match="height_fusion.mahalanobis_gate"):
        stridemap.PipelineOptions.from_config(str(config))
