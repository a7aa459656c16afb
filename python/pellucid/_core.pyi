"""
pellucid's compiled core (use the `pellucid` package, not this module)
"""
from __future__ import annotations
import collections.abc
import numpy
import numpy.typing
import typing
__all__: list[str] = ['BSDFProbe', 'BSSRDFProfile', 'BXDF_FLAGS', 'Error', 'FilmState', 'PhaseProbe', 'RenderProgress', 'Scene', 'aov_channels', 'aov_names', 'bssrdf_from_diffuse', 'bssrdf_searchlight', 'bssrdf_total', 'cancel', 'check_image_output', 'check_parameter_path', 'exit_lobe_norm', 'fresnel_moment', 'load_dict', 'load_file', 'load_film_state', 'mitsuba_import_table', 'read_image', 'read_image_attributes', 'read_layers', 'record_parameters', 'registry_types', 'render_aov', 'render_full', 'scene_parameters', 'set_log_sink', 'update_scene', 'write_image', 'write_image_with_attributes', 'write_layers']
class Error(RuntimeError):
    pass
class PhaseProbe:
    """
    One phase function (see pellucid.phase).
    """
    def __init__(self, desc: dict) -> None:
        ...
    def __repr__(self) -> str:
        ...
    def eval(self, wo: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], wi: typing.Annotated[numpy.typing.ArrayLike, numpy.float32]) -> numpy.typing.NDArray[numpy.float32]:
        """
        p(wo, wi) in 1/sr per row, (N,).
        """
    def pdf(self, wo: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], wi: typing.Annotated[numpy.typing.ArrayLike, numpy.float32]) -> numpy.typing.NDArray[numpy.float32]:
        """
        Solid-angle pdf of wi per row, (N,).
        """
    def sample(self, wo: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], u: typing.Annotated[numpy.typing.ArrayLike, numpy.float32]) -> tuple:
        """
        (wi, weight, pdf, delta) for u = (u1, u2).
        """
class BSDFProbe:
    """
    One material's BxDF at a default hit (see pellucid.bsdf).
    """
    def __init__(self, desc: dict, mode: str = 'radiance') -> None:
        ...
    def __repr__(self) -> str:
        ...
    def albedo(self, wo: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], n_samples: typing.SupportsInt | typing.SupportsIndex, seed: typing.SupportsInt | typing.SupportsIndex = 1, threads: typing.SupportsInt | typing.SupportsIndex = 0) -> numpy.typing.NDArray[numpy.float32]:
        """
        Mean sample weight per row of wo, (N, 3).
        """
    def benchmark(self, n: typing.SupportsInt | typing.SupportsIndex) -> dict:
        """
        Single-thread ns per eval/pdf/sample call.
        """
    def eval(self, wo: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], wi: typing.Annotated[numpy.typing.ArrayLike, numpy.float32]) -> numpy.typing.NDArray[numpy.float32]:
        """
        f·|cos θi| per row, (N, 3).
        """
    def pdf(self, wo: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], wi: typing.Annotated[numpy.typing.ArrayLike, numpy.float32]) -> numpy.typing.NDArray[numpy.float32]:
        """
        Solid-angle pdf of wi per row, (N,).
        """
    def sample(self, wo: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], u: typing.Annotated[numpy.typing.ArrayLike, numpy.float32]) -> tuple:
        """
        (wi, weight, pdf, lobe) for u = (u_lobe, u1, u2).
        """
    @property
    def flags(self) -> int:
        ...
class BSSRDFProfile:
    """
    One colour channel's diffusion profile (see pellucid.bssrdf.profile).
    """
    def __init__(self, model: str, sigma_a: typing.SupportsFloat | typing.SupportsIndex, sigma_s: typing.SupportsFloat | typing.SupportsIndex, g: typing.SupportsFloat | typing.SupportsIndex, eta: typing.SupportsFloat | typing.SupportsIndex) -> None:
        ...
    def eval(self, r: typing.Annotated[numpy.typing.ArrayLike, numpy.float32]) -> numpy.typing.NDArray[numpy.float32]:
        """
        R(r) in 1/length², elementwise.
        """
    def pdf(self, r: typing.Annotated[numpy.typing.ArrayLike, numpy.float32]) -> numpy.typing.NDArray[numpy.float32]:
        """
        Density of sample() per unit area at radius r, elementwise.
        """
    def sample(self, u: typing.Annotated[numpy.typing.ArrayLike, numpy.float32]) -> numpy.typing.NDArray[numpy.float32]:
        """
        Radii for u in [0, 1), elementwise.
        """
    @property
    def diffusion_length(self) -> float:
        ...
    @property
    def mean_free_path(self) -> float:
        ...
    @property
    def model(self) -> str:
        ...
    @property
    def r_max(self) -> float:
        ...
    @property
    def reduced_albedo(self) -> float:
        ...
    @property
    def total(self) -> float:
        ...
class Scene:
    """
    A built scene. Rendering reads it; pellucid.parameters(scene).update() changes it in place.
    """
    def __repr__(self) -> str:
        ...
    @property
    def bvh_builds(self) -> int:
        """
        Times the BVH was built: 1 when loaded, +1 per parameter update that moved geometry.
        """
    @property
    def height(self) -> int:
        ...
    @property
    def source(self) -> str:
        ...
    @property
    def spp(self) -> int:
        ...
    @property
    def subsurface_choices(self) -> list:
        """
        Per object of a subsurface material: the model that renders it and why (docs/subsurface.md).
        """
    @property
    def updates(self) -> int:
        """
        Parameter updates applied (pellucid.parameters).
        """
    @property
    def width(self) -> int:
        ...
class RenderProgress:
    """
    Progress of a running render, polled from another thread.
    """
    def __init__(self) -> None:
        ...
    def __repr__(self) -> str:
        ...
    @property
    def fraction(self) -> float:
        ...
    @property
    def samples(self) -> int:
        ...
class FilmState:
    """
    The film of a render after `spp` complete passes, with its seed and sampler: pass it as render(..., resume=state) to continue to more samples, or save() it for --resume.
    """
    def __repr__(self) -> str:
        ...
    def save(self, path: str) -> None:
        """
        Write the film state file (docs/rendering.md).
        """
    @property
    def height(self) -> int:
        ...
    @property
    def integrator(self) -> str:
        ...
    @property
    def invalid_samples(self) -> int:
        ...
    @property
    def sampler(self) -> str:
        ...
    @property
    def seconds(self) -> float:
        ...
    @property
    def seed(self) -> int:
        ...
    @property
    def spp(self) -> int:
        ...
    @property
    def width(self) -> int:
        ...
def aov_channels(name: str) -> list[str]:
    """
    The channel names of an AOV's layer in a multi-layer EXR (['R', 'G', 'B'], ['Z'], ...).
    """
def aov_names() -> list[str]:
    """
    Every AOV name render_full(aovs=...) accepts.
    """
def bssrdf_from_diffuse(model: str, albedo: typing.SupportsFloat | typing.SupportsIndex, mfp: typing.SupportsFloat | typing.SupportsIndex, g: typing.SupportsFloat | typing.SupportsIndex, eta: typing.SupportsFloat | typing.SupportsIndex) -> tuple[float, float]:
    """
    (sigma_a, sigma_s) of a diffuse albedo and mean free path.
    """
def bssrdf_searchlight(sigma_a: typing.SupportsFloat | typing.SupportsIndex, sigma_s: typing.SupportsFloat | typing.SupportsIndex, g: typing.SupportsFloat | typing.SupportsIndex, eta: typing.SupportsFloat | typing.SupportsIndex, thickness: typing.SupportsFloat | typing.SupportsIndex, photons: typing.SupportsInt | typing.SupportsIndex, seed: typing.SupportsInt | typing.SupportsIndex, r_edges: collections.abc.Sequence[typing.SupportsFloat | typing.SupportsIndex], max_collisions: typing.SupportsInt | typing.SupportsIndex, threads: typing.SupportsInt | typing.SupportsIndex) -> dict:
    """
    The searchlight random walk (see pellucid.bssrdf.searchlight).
    """
def bssrdf_total(model: str, reduced_albedo: typing.SupportsFloat | typing.SupportsIndex, eta: typing.SupportsFloat | typing.SupportsIndex) -> float:
    """
    The profile's total for a reduced albedo.
    """
def cancel() -> None:
    """
    Ask the running render to stop (it returns its complete passes).
    """
def check_image_output(path: str) -> None:
    """
    Check an output image path before rendering: a writable format, missing folders created.
    """
def check_parameter_path(scene: Scene, path: str, allow_new: bool = True) -> None:
    """
    Raise pellucid.Error unless path names a parameter of the scene (allow_new: or a key it may add).
    """
def exit_lobe_norm(eta: typing.SupportsFloat | typing.SupportsIndex) -> float:
    """
    c = 1 − 2 C1(eta, external).
    """
def fresnel_moment(i: typing.SupportsInt | typing.SupportsIndex, eta: typing.SupportsFloat | typing.SupportsIndex, internal: bool) -> float:
    """
    C_i = ∫0^1 F(μ) μ^i dμ.
    """
def load_dict(d: dict, base_dir: str = '.') -> Scene:
    """
    Build a scene from a dict with the JSON format's structure.
    """
def load_file(path: str, lenient: bool = False, params: collections.abc.Mapping[str, str] = {}) -> Scene:
    """
    Load and build a scene file (.json or Mitsuba 3 .xml; lenient: unsupported XML elements warn; params: Mitsuba $name values).
    """
def load_film_state(path: str) -> FilmState:
    """
    Read a film state file written by FilmState.save or pellucid-render --state.
    """
def mitsuba_import_table() -> list[dict[str, typing.Any]]:
    """
    The Mitsuba XML importer's mappings: [{kind, plugin, type, params: [(mitsuba, ours or 'ignored')]}].
    """
def read_image(path: str) -> numpy.ndarray:
    """
    Read every channel of an image as a linear float32 (H, W, C) array.
    """
def read_image_attributes(path: str) -> dict:
    """
    The header attributes of an image file as a dict.
    """
def read_layers(path: str) -> list:
    """
    An image file's layers as [(name, channel names, array)]. Use pellucid.read_layers.
    """
def record_parameters(d: dict, base_dir: str = '.') -> list[tuple]:
    """
    Build d; return (path, type, keys looked up) per object.
    """
def registry_types() -> dict[str, list[str]]:
    """
    Registered type names per family (materials, shapes, ...).
    """
def render_aov(scene: Scene, aov: str, spp: typing.SupportsInt | typing.SupportsIndex = -1, seed: typing.SupportsInt | typing.SupportsIndex = -1, threads: typing.SupportsInt | typing.SupportsIndex = 0, sampler: str = '') -> tuple[numpy.ndarray, numpy.ndarray]:
    """
    Render one AOV; returns (image, variance). Use pellucid.aov.render_aov for the documented API.
    """
def render_full(scene: Scene, spp: typing.SupportsInt | typing.SupportsIndex = -1, seed: typing.SupportsInt | typing.SupportsIndex = -1, threads: typing.SupportsInt | typing.SupportsIndex = 0, time_budget: typing.SupportsFloat | typing.SupportsIndex = 0.0, target_rel_error: typing.SupportsFloat | typing.SupportsIndex = 0.0, progress: bool = False, monitor: RenderProgress = None, sampler: str = '', resume: typing.Any = None, keep_state: bool = False, aov: str = '', aovs: collections.abc.Sequence[str] = [], variance: bool = True) -> tuple:
    """
    Render; returns (image, variance, stats) (variance None when variance is off and the film kept none), stats['state'] the FilmState if keep_state, stats['aovs'] {name: array} of the requested AOVs (integrator/aov.h) with stats['aov_seconds']. A Python signal handler that raises (Ctrl-C) stops it: the exception is raised with .partial = that tuple. Use pellucid.render for the documented API.
    """
def scene_parameters(scene: Scene) -> dict:
    """
    Every parameter of the scene's description: key path -> value (pellucid.parameters).
    """
def set_log_sink(fn: typing.Any) -> None:
    """
    Route log messages to fn(level: int, message: str); None restores stderr.
    """
def update_scene(scene: Scene, edits: dict) -> dict:
    """
    Set key path -> value in the scene's description and rebuild what depends on them, in place; returns {geometry, full, shapes_rebuilt, seconds}. On error the scene is unchanged.
    """
def write_image(path: str, array: typing.Annotated[numpy.typing.ArrayLike, numpy.float32]) -> None:
    """
    Write an (H, W) or (H, W, C) float array (.exr linear, any C; .png sRGB, C from 1 to 4).
    """
def write_image_with_attributes(path: str, array: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], attributes: dict) -> None:
    """
    write_image with header attributes (EXR attributes; formats without a header drop them).
    """
def write_layers(path: str, layers: list, attributes: dict) -> None:
    """
    Write [(name, channel names, array)] as one multi-layer EXR. Use pellucid.write_layers.
    """
BXDF_FLAGS: dict = {'reflection': 1, 'transmission': 2, 'diffuse': 4, 'glossy': 8, 'specular': 16}
__version__: str = '0.1.0'
