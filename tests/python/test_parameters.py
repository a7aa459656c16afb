"""pellucid.parameters(scene): key paths, in-place updates that render exactly as the edited scene
loaded afresh, what an update rebuilds, and its errors."""
from __future__ import annotations

import copy
from typing import Any, Dict

import numpy as np
import pytest

import pellucid

SEED = 5


def scene_dict() -> Dict[str, Any]:
    """A small scene with one of each kind of parameter: a named texture, named and inline
    materials, a sphere, an inline triangle mesh, an area light, point and constant lights."""
    return {
        "film": {"width": 24, "height": 18},
        "sampler": {"sample_count": 4, "seed": 0},
        "integrator": {"type": "path", "max_depth": 4},
        "camera": {"type": "perspective", "fov": 40,
                   "to_world": [{"look_at": {"origin": [0, 1.2, 4], "target": [0, 0.4, 0], "up": [0, 1, 0]}}]},
        "textures": {"checker": {"type": "checkerboard", "color0": 0.8, "color1": 0.1,
                                 "to_uv": [{"scale": [4, 4, 1]}]}},
        "materials": {
            "ball": {"type": "rough_plastic", "diffuse_reflectance": [0.7, 0.2, 0.2], "alpha": 0.2},
            "floor": {"type": "lambertian", "reflectance": "checker"},
            "metal": {"type": "rough_conductor", "material": "Au", "alpha": 0.3},
        },
        "shapes": [
            {"type": "rectangle", "material": "floor",
             "to_world": [{"scale": 5}, {"rotate": {"axis": [1, 0, 0], "angle": -90}}]},
            {"type": "sphere", "center": [0, 0.5, 0], "radius": 0.5, "material": "ball"},
            {"type": "mesh", "material": "metal",
             "positions": [-1.5, 0, -1, -0.5, 0, -1, -1, 1.2, -1], "indices": [0, 1, 2]},
            {"type": "rectangle", "material": {"type": "lambertian", "reflectance": 0.5},
             "to_world": [{"scale": 0.5}, {"rotate": {"axis": [1, 0, 0], "angle": 90}}, {"translate": [0, 2.5, 0]}],
             "emitter": {"type": "area", "radiance": 4}},
        ],
        "lights": [{"type": "point", "position": [1.5, 3, 2], "intensity": 8},
                   {"type": "constant", "radiance": 0.1}],
    }


def set_path(d: Dict[str, Any], path: str, value: Any) -> None:
    """Set a key path ("materials.ball.alpha", "shapes[1].radius") in a scene dict."""
    parts = []
    for part in path.split("."):
        while "[" in part:
            name, rest = part.split("[", 1)
            if name:
                parts.append(name)
            index, part = rest.split("]", 1)
            parts.append(int(index))
        if part:
            parts.append(part)
    node: Any = d
    for p in parts[:-1]:
        node = node[p]
    node[parts[-1]] = value


def render(scene: pellucid.Scene) -> np.ndarray:
    return np.array(pellucid.render(scene, seed=SEED))


def test_keys_are_the_scene_formats_key_paths() -> None:
    params = pellucid.parameters(pellucid.load_dict(scene_dict()))
    keys = set(params)
    for key in ["camera.fov", "camera.to_world", "film.width", "sampler.sample_count",
                "textures.checker.color0", "textures.checker.to_uv", "materials.ball.alpha",
                "materials.ball.diffuse_reflectance", "materials.floor.reflectance", "shapes[0].to_world",
                "shapes[1].center", "shapes[1].radius", "shapes[2].positions", "shapes[3].material.reflectance",
                "shapes[3].emitter.radiance", "lights[0].intensity", "lights[1].radiance"]:
        assert key in keys, key
    assert not any(k.endswith(".type") or k == "type" for k in keys)  # a type is not a parameter
    assert params["materials.ball.alpha"] == 0.2
    assert params["shapes[1].center"] == [0, 0.5, 0]
    assert params["materials.floor.reflectance"] == "checker"
    assert len(params) == len(keys)


# (key path, new value, whether the geometry moves)
EDITS = [
    ("materials.ball.diffuse_reflectance", [0.1, 0.6, 0.3], False),       # a material colour
    ("materials.metal.alpha", 0.05, False),
    ("textures.checker.color1", [0.9, 0.1, 0.1], False),                 # a named texture
    ("shapes[3].material.reflectance", 0.9, False),                      # an inline material
    ("lights[1].radiance", 0.4, False),                                   # a light: new selection CDF
    ("shapes[3].emitter.radiance", [9, 6, 3], False),                     # an area light
    ("camera.to_world", [{"look_at": {"origin": [1, 2, 3], "target": [0, 0.3, 0], "up": [0, 1, 0]}}], False),
    ("camera.fov", 55, False),
    ("shapes[1].center", [0.3, 0.7, 0.2], True),                          # a sphere moves
    ("shapes[1].radius", 0.8, True),
    ("shapes[0].to_world", [{"scale": 3}, {"rotate": {"axis": [1, 0, 0], "angle": -80}}], True),
    ("shapes[2].positions", [-1.5, 0, -1, -0.2, 0.1, -1, -1, 1.6, -0.8], True),  # vertex positions
]


@pytest.mark.parametrize("key,value,geometry", EDITS, ids=[e[0] for e in EDITS])
def test_update_renders_as_the_edited_scene_loaded_afresh(key: str, value: Any, geometry: bool) -> None:
    scene = pellucid.load_dict(scene_dict())
    before = render(scene)
    params = pellucid.parameters(scene)
    params[key] = value
    assert params[key] == value  # pending assignments read back
    report = params.update()
    assert report["geometry"] is geometry and not report["full"]
    assert scene.updates == 1
    assert scene.bvh_builds == (2 if geometry else 1)  # the BVH is built again only when geometry moved
    edited = scene_dict()
    set_path(edited, key, value)
    expected = render(pellucid.load_dict(edited))
    got = render(scene)
    assert not np.array_equal(expected, before), "the edit must change the image"
    assert np.array_equal(got, expected)
    assert pellucid.parameters(scene)[key] == value


def test_several_updates_in_a_row_and_a_default_key() -> None:
    scene = pellucid.load_dict(scene_dict())
    params = pellucid.parameters(scene)
    edited = scene_dict()
    for alpha in (0.0, 0.5, 1.0):
        params["materials.ball.alpha"] = alpha
        params.update()
    edited["materials"]["ball"]["alpha"] = 1.0
    # A key the scene leaves at its default can be set as well.
    params.update({"materials.metal.multiple_scattering": True, "lights[1].radiance": 0.3})
    edited["materials"]["metal"]["multiple_scattering"] = True
    edited["lights"][1]["radiance"] = 0.3
    assert scene.updates == 4 and scene.bvh_builds == 1
    assert np.array_equal(render(scene), render(pellucid.load_dict(edited)))


def test_a_mesh_and_a_sphere_move_together_and_the_rest_is_kept() -> None:
    scene = pellucid.load_dict(scene_dict())
    params = pellucid.parameters(scene)
    report = params.update({"shapes[1].radius": 0.3, "materials.ball.alpha": 0.4})
    assert report["geometry"] and report["shapes_rebuilt"] == 1
    edited = scene_dict()
    edited["shapes"][1]["radius"] = 0.3
    edited["materials"]["ball"]["alpha"] = 0.4
    assert np.array_equal(render(scene), render(pellucid.load_dict(edited)))


def test_a_material_reference_and_a_new_emitter() -> None:
    scene = pellucid.load_dict(scene_dict())
    params = pellucid.parameters(scene)
    report = params.update({"shapes[1].material": "metal",
                            "shapes[2].emitter": {"type": "area", "radiance": [2, 2, 5], "two_sided": True}})
    assert not report["geometry"] and scene.bvh_builds == 1
    edited = scene_dict()
    edited["shapes"][1]["material"] = "metal"
    edited["shapes"][2]["emitter"] = {"type": "area", "radiance": [2, 2, 5], "two_sided": True}
    assert np.array_equal(render(scene), render(pellucid.load_dict(edited)))
    # An inline material where a name was: material ids may move, so everything is built anew.
    report = params.update({"shapes[1].material": {"type": "lambertian", "reflectance": [0.2, 0.2, 0.9]}})
    assert report["full"] and scene.bvh_builds == 2
    edited["shapes"][1]["material"] = {"type": "lambertian", "reflectance": [0.2, 0.2, 0.9]}
    assert np.array_equal(render(scene), render(pellucid.load_dict(edited)))
    assert pellucid.parameters(scene)["shapes[1].material.reflectance"] == [0.2, 0.2, 0.9]


def test_film_size_changes_the_camera_too() -> None:
    scene = pellucid.load_dict(scene_dict())
    pellucid.parameters(scene).update({"film.width": 16, "film.height": 20})
    edited = scene_dict()
    edited["film"].update(width=16, height=20)
    got = render(scene)
    assert got.shape == (20, 16, 3) and scene.width == 16
    assert np.array_equal(got, render(pellucid.load_dict(edited)))


def test_unknown_key_paths_get_a_suggestion() -> None:
    scene = pellucid.load_dict(scene_dict())
    params = pellucid.parameters(scene)
    with pytest.raises(pellucid.Error, match=r"materials\.bal\.alpha: unknown parameter \(did you mean "
                                             r"'materials\.ball\.alpha'"):
        params["materials.bal.alpha"] = 0.3
    with pytest.raises(pellucid.Error, match=r"lights\[7\]\.radiance: unknown parameter"):
        params["lights[7].radiance"] = 1
    with pytest.raises(pellucid.Error, match="not a parameter"):
        params["materials.ball"] = {"type": "lambertian"}
    with pytest.raises(pellucid.Error, match="type is not a parameter"):
        params["materials.ball.type"] = "lambertian"
    with pytest.raises(KeyError, match="did you mean 'camera.fov'"):
        params["camera.fvo"]
    with pytest.raises(KeyError, match="a key left at its default can be set, not read"):
        params["camera.fov_axis"]
    # A key the object does not take: the builder's own message, with its suggestion.
    before = render(scene)
    params["materials.ball.alpah"] = 0.3
    with pytest.raises(pellucid.Error, match=r"<dict>: materials\.ball\.alpah: unknown parameter \(did you mean 'alpha'"):
        params.update()
    assert scene.updates == 0 and not params.pending
    assert np.array_equal(render(scene), before)


@pytest.mark.parametrize("key,value,message", [
    ("materials.ball.alpha", "rough", r"materials\.ball\.alpha: .*string"),
    ("materials.ball.diffuse_reflectance", [0.1, 0.2], r"materials\.ball\.diffuse_reflectance: expected a number or an "
                                                       r"array of 3 numbers, got a array of 2 elements"),
    ("lights[1].radiance", -1, r"lights\[1\]\.radiance: value \[-1\.0+, -1\.0+, -1\.0+\] must be >= 0"),
    ("camera.fov", 200, r"camera\.fov: value 200\.0+ must be in \(0, 180\)"),
    ("shapes[1].radius", -2, r"shapes\[1\]\.radius: value -2\.0+ must be > 0"),
    ("shapes[2].positions", [0, 0, 0, 1], r"shapes\[2\]\.positions: expected a non-empty flat array of x,y,z triples"),
    ("textures.checker.color0", {"type": "checkerboard"}, r"textures\.checker\.color0: expected a number or an array"),
    ("materials.ball.diffuse_reflectance", {"type": "nope"}, r"materials\.ball\.diffuse_reflectance\.type: unknown"),
])
def test_bad_values_raise_the_loaders_error_and_leave_the_scene(key: str, value: Any, message: str) -> None:
    scene = pellucid.load_dict(scene_dict())
    before = render(scene)
    params = pellucid.parameters(scene)
    params["materials.ball.alpha"] = 0.7  # a good edit in the same batch is dropped too
    params[key] = value
    with pytest.raises(pellucid.Error, match=message):
        params.update()
    edited = scene_dict()
    set_path(edited, key, value)
    with pytest.raises(pellucid.Error, match=message):  # the same message as loading it
        pellucid.load_dict(edited)
    assert scene.updates == 0 and scene.bvh_builds == 1
    assert np.array_equal(render(scene), before)
    assert pellucid.parameters(scene)["materials.ball.alpha"] == 0.2


def test_a_failed_update_restores_the_description() -> None:
    scene = pellucid.load_dict(scene_dict())
    params = pellucid.parameters(scene)
    values = dict(params)
    with pytest.raises(pellucid.Error, match=r"camera\.fov: value 500"):
        params.update({"materials.metal.multiple_scattering": True, "shapes[1].radius": 2.0,
                       "textures.checker.color0": 0.3, "camera.fov": 500})
    fresh = pellucid.parameters(scene)
    assert dict(fresh) == values and "materials.metal.multiple_scattering" not in fresh
    params.update({"camera.fov": 50})  # and the scene still updates
    edited = scene_dict()
    edited["camera"]["fov"] = 50
    assert np.array_equal(render(scene), render(pellucid.load_dict(edited)))


def test_values_are_copies_and_parameters_cannot_be_removed() -> None:
    scene = pellucid.load_dict(scene_dict())
    params = pellucid.parameters(scene)
    params["shapes[1].center"].append(5)
    assert params["shapes[1].center"] == [0, 0.5, 0]
    with pytest.raises(pellucid.Error, match="cannot be removed"):
        del params["camera.fov"]
    assert "camera.fov" in repr(params)
    other = pellucid.parameters(scene)
    params.update({"camera.fov": 30})
    assert other["camera.fov"] == 30  # every mapping of the scene sees its updates


def test_a_file_scene_keeps_its_base_dir(tmp_path) -> None:
    d = scene_dict()
    (tmp_path / "tri.obj").write_text("v -1 0 -1\nv 1 0 -1\nv 0 1.5 -1\nf 1 2 3\n")
    d["shapes"][2] = {"type": "obj", "filename": "tri.obj", "material": "metal"}
    import json
    (tmp_path / "scene.json").write_text(json.dumps(d))
    scene = pellucid.load_file(tmp_path / "scene.json")
    params = pellucid.parameters(scene)
    params.update({"shapes[2].to_world": [{"translate": [0.5, 0, 0]}], "shapes[2].material": "ball"})
    d["shapes"][2]["to_world"] = [{"translate": [0.5, 0, 0]}]
    d["shapes"][2]["material"] = "ball"
    assert scene.bvh_builds == 2
    assert np.array_equal(render(scene), render(pellucid.load_dict(copy.deepcopy(d), base_dir=tmp_path)))


XML = """<scene version="3.0.0">
  <default name="alpha" value="0.1"/>
  <integrator type="path"><integer name="max_depth" value="4"/></integrator>
  <sensor type="perspective">
    <float name="fov" value="40"/>
    <transform name="to_world"><lookat origin="0, 0, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
    <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
    <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="12"/></film>
  </sensor>
  <bsdf type="roughconductor" id="metal"><float name="alpha" value="$alpha"/><string name="material" value="Cu"/></bsdf>
  <shape type="sphere"><ref id="metal"/></shape>
  <emitter type="constant"><rgb name="radiance" value="0.5, 0.6, 0.7"/></emitter>
  <emitter type="point"><point name="position" x="2" y="2" z="3"/><rgb name="intensity" value="5"/></emitter>
</scene>
"""


def test_a_mitsuba_xml_scene_has_the_key_paths_of_its_conversion(tmp_path) -> None:
    path = tmp_path / "scene.xml"
    path.write_text(XML)
    scene = pellucid.load_file(path)
    params = pellucid.parameters(scene)
    assert params["materials.metal.alpha"] == 0.1 and params["lights[1].intensity"] == 5.0
    params.update({"materials.metal.alpha": 0.4})
    expected = render(pellucid.load_file(path, alpha=0.4))
    assert not np.array_equal(expected, render(pellucid.load_file(path)))
    assert np.array_equal(render(scene), expected)
    with pytest.raises(pellucid.Error, match=r"scene\.xml: materials\.metal\.alpha: expected a number"):
        params.update({"materials.metal.alpha": "rough"})


def fog_dict() -> Dict[str, Any]:
    import json
    import pathlib
    d = json.loads((pathlib.Path(__file__).resolve().parents[2] / "scenes" / "fog.json").read_text())
    d["film"] = {"width": 16, "height": 16}
    d["sampler"] = {"sample_count": 4, "seed": 0}
    d["media"]["thick"] = {"type": "homogeneous", "sigma_t": 4.0, "albedo": [0.9, 0.5, 0.3]}
    return d


@pytest.mark.parametrize("values,geometry", [
    ({"media.fog.sigma_t": 1.5, "media.fog.phase.g": -0.3}, False),          # a medium and its phase function
    ({"shapes[8].interior": "thick", "shapes[6].exterior": "thick"}, False),  # media references of shapes
    ({"shapes[2].material": "boundary"}, True),                              # a null surface: ids may move
], ids=["medium", "shape media", "null material"])
def test_media_parameters_update_as_a_fresh_load(values: Dict[str, Any], geometry: bool) -> None:
    scene = pellucid.load_dict(fog_dict())
    params = pellucid.parameters(scene)
    assert params["media.fog.sigma_t"] == 0.6 and params["media.fog.phase.g"] == 0.7
    report = params.update(values)
    assert report["geometry"] is geometry
    edited = fog_dict()
    for k, v in values.items():
        set_path(edited, k, v)
    expected = render(pellucid.load_dict(edited))
    assert not np.array_equal(expected, render(pellucid.load_dict(fog_dict())))
    assert np.array_equal(render(scene), expected)
