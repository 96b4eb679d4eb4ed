"""A roll or pitch beyond 60 degrees is a warning naming the value: most
likely degrees passed where radians belong. Never an error."""
import warnings

import numpy as np
import pytest

import stridemap

BEAMS = stridemap.UrgParameters().beam_count


def no_warning(call, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return call(*args, **kwargs)


def test_a_pose_in_degrees_warns_naming_the_angle():
    pipeline = stridemap.Pipeline()
    with pytest.warns(UserWarning, match=r"^pose: roll or pitch beyond 60 deg: pitch_rad 35 \(2005\.4 deg\); "
                                         r"poses take radians"):
        outcome = pipeline.add_urg_scan(np.full(BEAMS, 1000), 0.0, [0.0, 0.0, 0.0, 35.0, 0.0])
    assert outcome["reached_mapper"] in (True, False)  # mapped or not, the call went through
    with pytest.warns(UserWarning, match=r"roll_rad -2 \(-114\.6 deg\) and pitch_rad 1\.5"):
        pipeline.add_urg_scan(np.full(BEAMS, 1000), 0.1, [0.0, 0.0, -2.0, 1.5, 0.0])


def test_plausible_tilts_do_not_warn():
    limit = np.radians(59.9)
    no_warning(stridemap.Pipeline().add_urg_scan, np.full(BEAMS, 1000), 0.0, [0.0, 0.0, limit, -limit, 7.0])  # yaw is free
    pipeline = stridemap.Pipeline(stridemap.PipelineOptions(sensor="points"))
    no_warning(pipeline.add_points, np.zeros((1, 3)), 0.01, 0.1, [0.0, 0.0, 0.0, 0.2, -0.3, 3.0])


def test_six_value_poses_warn_on_their_own_roll_and_pitch():
    pipeline = stridemap.Pipeline(stridemap.PipelineOptions(sensor="points"))
    # z_m = 5 is a height, not an angle: no warning; pitch 80 is one.
    no_warning(pipeline.add_points, np.zeros((1, 3)), 0.01, 0.0, [0.0, 0.0, 5.0, 0.0, 0.0, 0.0])
    with pytest.warns(UserWarning, match=r"^pose: roll or pitch beyond 60 deg: pitch_rad 80"):
        pipeline.add_points(np.zeros((1, 3)), 0.01, 0.1, [0.0, 0.0, 0.3, 0.0, 80.0, 0.0])


def test_many_poses_warn_once_naming_the_first_and_how_many():
    pipeline = stridemap.Pipeline()
    poses = np.zeros((4, 5))
    poses[2, 2] = 10.0
    poses[3, 3] = -90.0
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        pipeline.add_urg_scans(np.full((4, BEAMS), 1000), [0.0, 0.1, 0.2, 0.3], poses)
    tilt = [w for w in caught if issubclass(w.category, UserWarning) and "60 deg" in str(w.message)]
    assert len(tilt) == 1
    assert "poses: 2 of 4 poses tilt beyond 60 deg" in str(tilt[0].message)
    assert "the first poses[2]: roll_rad 10 (573.0 deg)" in str(tilt[0].message)


def test_simulated_scans_and_saved_poses_warn_too(flat_scene, tmp_path):
    with pytest.warns(UserWarning, match=r"poses: 1 of 1 poses .* poses\[0\]: pitch_rad 45"):
        stridemap.simulate_urg_scans(flat_scene, [[0.0, 0.0, 0.0, 45.0, 0.0]], [0.0])
    pose = {"x_m": 0.0, "y_m": 0.0, "roll_rad": 70.0, "pitch_rad": 0.0, "yaw_rad": 0.0,
            "reference_elevation_m": 0.0, "height_change_m": 0.0}
    with pytest.warns(UserWarning, match=r"^last_pose: roll or pitch beyond 60 deg: roll_rad 70"):
        stridemap.Map(4, 0.1).save(tmp_path / "m.smap", last_pose=pose)


def test_warnings_as_errors_stop_the_call_before_it_maps():
    pipeline = stridemap.Pipeline()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(UserWarning, match="pitch_rad 30"):
            pipeline.add_urg_scans(np.full((1, BEAMS), 1000), [0.0], [[0.0, 0.0, 0.0, 30.0, 0.0]])
    assert pipeline.stats["scans"] == 0
