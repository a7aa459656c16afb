"""Scene parameters by key path, and updates of a built scene in place (as Mitsuba 3's
``mi.traverse(scene)`` and ``params.update()``)::

    params = pellucid.parameters(scene)
    params["materials.red.reflectance"] = [0.2, 0.8, 0.2]
    params["camera.fov"] = 30
    params.update()                      # the scene changes in place; render it again

Keys are the key paths of the scene format, the ones its error messages use
(``materials.red.reflectance``, ``lights[0].radiance``, ``shapes[2].to_world``, ``camera.fov``);
values are what a scene dict holds there (numbers, lists, strings, dicts). docs/parameters.md
describes what an update rebuilds.
"""
from __future__ import annotations

import copy as _copy
from typing import Any, Dict, Iterator, Mapping, MutableMapping, Optional

from . import _core
from ._core import Error, Scene

__all__ = ["SceneParameters", "parameters"]


class SceneParameters(MutableMapping[str, Any]):
    """Every parameter of a scene by key path. Assignments are kept until :meth:`update` applies
    them all at once; reading a key gives the assigned value until then.

    A key that the scene leaves at its default (not in its description) is not listed, but can be
    assigned when its object is a material, texture, light, emitter, shape, the camera, film,
    sampler or integrator: the scene builder then checks that the object takes it. Other unknown
    keys raise :class:`pellucid.Error` with the nearest key paths.

    Values are copies: assign a new value rather than changing a returned list in place.
    """

    def __init__(self, scene: Scene) -> None:
        if not isinstance(scene, Scene):
            raise Error(f"parameters: expected a pellucid.Scene, got {type(scene).__name__}")
        self._scene = scene
        self._values: Dict[str, Any] = {}
        self._seen = -1
        self._pending: Dict[str, Any] = {}

    @property
    def scene(self) -> Scene:
        return self._scene

    def _current(self) -> Dict[str, Any]:
        """The scene's parameters, read again after any update of the scene."""
        if self._seen != self._scene.updates:
            self._values = _core.scene_parameters(self._scene)
            self._seen = self._scene.updates
        return self._values

    def __getitem__(self, key: str) -> Any:
        if key in self._pending:
            return _copy.deepcopy(self._pending[key])
        values = self._current()
        if key in values:
            return _copy.deepcopy(values[key])
        try:
            _core.check_parameter_path(self._scene, key, allow_new=False)
        except Error as e:
            raise KeyError(str(e)) from None
        raise KeyError(key)  # not reached: check_parameter_path raises for a key that is not listed

    def __setitem__(self, key: str, value: Any) -> None:
        if not isinstance(key, str):
            raise Error(f"parameters: key paths are strings, got {type(key).__name__}")
        if key not in self._current():
            _core.check_parameter_path(self._scene, key)
        self._pending[key] = value

    def __delitem__(self, key: str) -> None:
        raise Error(f"{key}: parameters cannot be removed (assign a value instead)")

    def __iter__(self) -> Iterator[str]:
        values = self._current()
        yield from values
        yield from (k for k in self._pending if k not in values)

    def __len__(self) -> int:
        values = self._current()
        return len(values) + sum(1 for k in self._pending if k not in values)

    @property
    def pending(self) -> Dict[str, Any]:
        """The assignments that :meth:`update` will apply."""
        return dict(self._pending)

    def update(self, values: Optional[Mapping[str, Any]] = None) -> Dict[str, Any]:  # type: ignore[override]
        """Assign ``values`` (key path -> value) if given, then apply every pending assignment to
        the scene in place, rebuilding only what depends on them (the BVH only when geometry
        moved). Returns ``{"geometry": bool, "full": bool, "shapes_rebuilt": int, "seconds":
        float}``: whether the BVH was built anew, whether everything was, how many shapes' geometry
        was built anew, and how long it took.

        Raises :class:`pellucid.Error` naming the key path and the value, as loading the edited
        scene would; the scene is then unchanged and the pending assignments are dropped.
        """
        if values is not None:
            for k, v in values.items():
                self[k] = v
        if not self._pending:
            return {"geometry": False, "full": False, "shapes_rebuilt": 0, "seconds": 0.0}
        edits, self._pending = self._pending, {}
        return _core.update_scene(self._scene, edits)

    def __repr__(self) -> str:
        lines = [f"SceneParameters({self._scene.source}, {len(self)} parameters)"]
        for key in self:
            text = repr(self[key])
            if len(text) > 60:
                text = text[:57] + "..."
            mark = " (pending)" if key in self._pending else ""
            lines.append(f"  {key}: {text}{mark}")
        return "\n".join(lines)


def parameters(scene: Scene) -> SceneParameters:
    """The parameters of ``scene`` by key path: a mutable mapping whose ``update()`` changes the
    scene in place (see :class:`SceneParameters`)."""
    return SceneParameters(scene)
