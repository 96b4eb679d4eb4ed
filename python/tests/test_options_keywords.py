"""Every option class takes its fields as keywords, says which keyword or
type is wrong, and shows its fields in its repr."""
import numpy as np
import pytest

import stridemap

OPTION_CLASSES = [stridemap.PipelineOptions, stridemap.UpdateOptions, stridemap.UrgParameters, stridemap.SensorMount]


def settable_fields(cls):
    return [name for name, member in vars(cls).items() if isinstance(member, property) and member.fset is not None]


def test_keywords_set_the_fields_and_leave_the_rest_at_their_defaults():
    options = stridemap.PipelineOptions(cells_per_side=200, cell_size_m=0.02, filters="paper", follow_robot=False)
    assert (options.cells_per_side, options.cell_size_m, options.follow_robot) == (200, 0.02, False)
    assert options.filters == "range-clustering,scan-sequence"
    assert options.map_filter == stridemap.PipelineOptions().map_filter
    nested = stridemap.PipelineOptions(update=stridemap.UpdateOptions(certainty_max=50.0, elevation_rule="gated"),
                                       mount=stridemap.SensorMount(height_m=0.4),
                                       urg=stridemap.UrgParameters(first_step=50))
    assert nested.update.certainty_max == 50.0 and nested.update.elevation_rule == "gated"
    assert nested.mount.height_m == 0.4 and nested.urg.first_step == 50
    # NumPy scalars are numbers like any other.
    assert stridemap.SensorMount(pitch_rad=np.float32(0.5)).pitch_rad == pytest.approx(0.5)
    assert stridemap.UrgParameters(last_step=np.int64(700)).last_step == 700


def test_sensor_mount_still_takes_its_fields_by_position():
    mount = stridemap.SensorMount(0.3, 0.5, 0.1)
    assert (mount.height_m, mount.pitch_rad, mount.forward_offset_m) == (0.3, 0.5, 0.1)
    with pytest.raises(TypeError, match="height_m both by position and by keyword"):
        stridemap.SensorMount(0.3, height_m=0.4)
    with pytest.raises(TypeError, match="at most 6 positional"):
        stridemap.SensorMount(1, 2, 3, 4, 5, 6, 7)


@pytest.mark.parametrize("cls", OPTION_CLASSES, ids=lambda c: c.__name__)
def test_an_unknown_keyword_is_named_with_the_fields_there_are(cls):
    with pytest.raises(TypeError) as error:
        cls(no_such_field=1)
    message = str(error.value)
    assert f"{cls.__name__}() got an unknown keyword 'no_such_field'" in message
    for field in settable_fields(cls):
        assert field in message


@pytest.mark.parametrize("cls", OPTION_CLASSES, ids=lambda c: c.__name__)
def test_a_wrong_type_names_the_field(cls):
    for field in settable_fields(cls):
        with pytest.raises(TypeError, match=rf"^{cls.__name__}\.{field}: expected \w+, got object"):
            cls(**{field: object()})


def test_counts_flags_and_numbers_are_not_mixed_up():
    with pytest.raises(TypeError, match=r"PipelineOptions\.cells_per_side: expected int, got float \(200\.0\)"):
        stridemap.PipelineOptions(cells_per_side=200.0)
    with pytest.raises(TypeError, match=r"PipelineOptions\.cells_per_side: expected int, got bool"):
        stridemap.PipelineOptions(cells_per_side=True)
    with pytest.raises(TypeError, match=r"PipelineOptions\.follow_robot: expected bool, got int"):
        stridemap.PipelineOptions(follow_robot=1)
    with pytest.raises(TypeError, match=r"PipelineOptions\.update: expected UpdateOptions, got SensorMount"):
        stridemap.PipelineOptions(update=stridemap.SensorMount())
    assert stridemap.PipelineOptions(cell_size_m=1).cell_size_m == 1.0  # an int is a fine number of metres


def test_a_value_the_field_refuses_names_the_field():
    with pytest.raises(stridemap.InputError, match=r"^PipelineOptions\.sensor: 'lidar' is not a sensor"):
        stridemap.PipelineOptions(sensor="lidar")
    with pytest.raises(stridemap.InputError, match=r"^UpdateOptions\.elevation_rule: "):
        stridemap.UpdateOptions(elevation_rule="highest")


def test_positional_arguments_are_refused_where_the_order_means_nothing():
    with pytest.raises(TypeError, match=r"PipelineOptions\(\) takes keyword arguments only \(its fields: sensor, "):
        stridemap.PipelineOptions(200)


@pytest.mark.parametrize("cls", OPTION_CLASSES, ids=lambda c: c.__name__)
def test_repr_shows_every_field_and_evaluates_back(cls):
    text = repr(cls())
    assert text.startswith(cls.__name__ + "(")
    for field in settable_fields(cls):
        assert f"{field}=" in text
    again = eval(text, {name: getattr(stridemap, name) for name in stridemap.__all__})
    assert repr(again) == text


def test_repr_shows_a_changed_field():
    assert "cells_per_side=321" in repr(stridemap.PipelineOptions(cells_per_side=321))
    assert "height_m=0.42" in repr(stridemap.SensorMount(height_m=0.42))


def test_the_stub_lists_every_field_as_a_keyword_of_init():
    import ast
    import os
    stub = os.path.join(os.path.dirname(stridemap.__file__), "__init__.pyi")
    with open(stub, encoding="utf-8") as f:
        classes = {node.name: node for node in ast.parse(f.read()).body if isinstance(node, ast.ClassDef)}
    for cls in OPTION_CLASSES:
        init = next(item for item in classes[cls.__name__].body
                    if isinstance(item, ast.FunctionDef) and item.name == "__init__")
        names = [a.arg for a in init.args.args[1:] + init.args.kwonlyargs]
        assert names == settable_fields(cls), cls.__name__
