"""``pellucid.materials``: one small builder per material type, returning the scene-format dict.

Each keyword is the JSON key of the same name; a keyword left at ``None`` is omitted, so the
renderer's default applies (defaults, ranges and models: docs/scene-format.md, ``## materials``).
The first parameter may be given positionally, the others by name::

    from pellucid import materials as M
    M.lambertian(0.8)                                   # {"type": "lambertian", "reflectance": 0.8}
    M.rough_conductor("Au", roughness=0.3)              # gold, α = 0.09
    M.rough_plastic([0.1, 0.3, 0.6], alpha=0.15)
    pellucid.bsdf(M.dielectric(1.5)).albedo([[0, 0, 1]])

Colours take a number (grey) or ``[r, g, b]``; IORs a number or a name (``"bk7"``, ``"water"``,
...); values are checked by the renderer when the scene (or ``pellucid.bsdf``) is built, with
errors naming the key and value.
"""
from __future__ import annotations

from typing import Any, Dict, Optional, Sequence, Union

Colour = Union[float, Sequence[float], Dict[str, Any]]  # a dict: a texture, where supported
IOR = Union[float, str]
Material = Dict[str, Any]

__all__ = [
    "conductor",
    "dielectric",
    "lambertian",
    "oren_nayar",
    "plastic",
    "principled",
    "rough_conductor",
    "rough_dielectric",
    "rough_plastic",
    "subsurface",
    "thin_dielectric",
]


def _make(type_name: str, params: Dict[str, Any]) -> Material:
    d: Material = {"type": type_name}
    d.update((k, v) for k, v in params.items() if v is not None)
    return d


# Keys every material takes (bump and normal maps, sidedness; docs/scene-format.md, "Bump and normal maps").
_SURFACE_KEYS = ("bump_map", "bump_scale", "bump_step_scale", "bump_model", "normal_map", "normal_map_convention",
                 "invalid_normals", "terminator_softening", "terminator_model", "two_sided")


def _with_surface_keys(fn):
    """Add the keyword-only surface keys (bump_map=..., normal_map=...) to a builder."""
    import functools
    import inspect

    sig = inspect.signature(fn)
    extra = [inspect.Parameter(k, inspect.Parameter.KEYWORD_ONLY, default=None) for k in _SURFACE_KEYS]

    @functools.wraps(fn)
    def wrapper(*args, **kwargs):
        surface = {k: kwargs.pop(k) for k in _SURFACE_KEYS if k in kwargs}
        d = fn(*args, **kwargs)
        d.update((k, v) for k, v in surface.items() if v is not None)
        return d

    wrapper.__signature__ = sig.replace(parameters=list(sig.parameters.values()) + extra)
    wrapper.__doc__ = (fn.__doc__ or "") + (
        "\n    Every material also takes ``bump_map``, ``bump_scale``, ``bump_step_scale``, ``bump_model``,"
        "\n    ``normal_map``, ``normal_map_convention``, ``invalid_normals``, ``terminator_softening``,"
        "\n    ``terminator_model`` and ``two_sided`` (docs/scene-format.md).\n")
    return wrapper


@_with_surface_keys
def lambertian(reflectance: Optional[Colour] = None) -> Material:
    """Ideal diffuse reflection, f = ρ/π. ``reflectance``: albedo ρ (default 0.5).

    docs/scene-format.md, ``### lambertian``.
    """
    return _make("lambertian", dict(reflectance=reflectance))


@_with_surface_keys
def oren_nayar(reflectance: Optional[Colour] = None, *, variant: Optional[str] = None,
               roughness: Optional[float] = None, sigma: Optional[float] = None) -> Material:
    """Rough diffuse reflection: ``variant="eon"`` (default; energy-preserving, takes
    ``roughness`` in [0, 1]) or ``"classic"`` (Oren & Nayar 1994, takes ``sigma`` in degrees).

    docs/scene-format.md, ``### oren_nayar``.
    """
    return _make("oren_nayar", dict(reflectance=reflectance, variant=variant, roughness=roughness, sigma=sigma))


@_with_surface_keys
def conductor(material: Optional[str] = None, *, eta: Optional[Colour] = None, k: Optional[Colour] = None,
              specular_reflectance: Optional[Colour] = None, fresnel: Optional[str] = None) -> Material:
    """Smooth metal. ``material``: a metal name (``"Au"``, ``"Ag"``, ``"Cu"``, ``"Al"``, ...,
    ``"none"`` = perfect mirror), or give the complex IOR ``eta`` + ``k`` instead.
    ``fresnel``: ``"exact"`` (default) or ``"schlick"``.

    docs/scene-format.md, ``### conductor``.
    """
    return _make("conductor", dict(material=material, eta=eta, k=k, specular_reflectance=specular_reflectance,
                                   fresnel=fresnel))


@_with_surface_keys
def rough_conductor(material: Optional[str] = None, *, eta: Optional[Colour] = None, k: Optional[Colour] = None,
                    specular_reflectance: Optional[Colour] = None, fresnel: Optional[str] = None,
                    distribution: Optional[str] = None, alpha: Optional[float] = None,
                    alpha_u: Optional[float] = None, alpha_v: Optional[float] = None,
                    roughness: Optional[float] = None, multiple_scattering: Optional[bool] = None,
                    shadowing: Optional[str] = None) -> Material:
    """Microfacet metal: the ``conductor`` parameters plus ``distribution`` (``"ggx"`` default,
    ``"beckmann"``), one of ``alpha`` / ``alpha_u`` + ``alpha_v`` / ``roughness`` (α = r²),
    ``multiple_scattering`` (Kulla–Conty energy compensation, GGX only) and ``shadowing``
    (``"height_correlated"`` default, ``"separable"``).

    docs/scene-format.md, ``### rough_conductor``.
    """
    return _make("rough_conductor", dict(material=material, eta=eta, k=k, specular_reflectance=specular_reflectance,
                                         fresnel=fresnel, distribution=distribution, alpha=alpha, alpha_u=alpha_u,
                                         alpha_v=alpha_v, roughness=roughness,
                                         multiple_scattering=multiple_scattering, shadowing=shadowing))


@_with_surface_keys
def dielectric(int_ior: Optional[IOR] = None, *, ext_ior: Optional[IOR] = None,
               specular_reflectance: Optional[Colour] = None,
               specular_transmittance: Optional[Colour] = None) -> Material:
    """Smooth glass-like interface (Fresnel reflection + Snell refraction). ``int_ior`` inside
    (default ``"bk7"``), ``ext_ior`` outside (default ``"air"``).

    docs/scene-format.md, ``### dielectric``.
    """
    return _make("dielectric", dict(int_ior=int_ior, ext_ior=ext_ior, specular_reflectance=specular_reflectance,
                                    specular_transmittance=specular_transmittance))


@_with_surface_keys
def rough_dielectric(int_ior: Optional[IOR] = None, *, ext_ior: Optional[IOR] = None,
                     specular_reflectance: Optional[Colour] = None,
                     specular_transmittance: Optional[Colour] = None, distribution: Optional[str] = None,
                     alpha: Optional[float] = None, alpha_u: Optional[float] = None,
                     alpha_v: Optional[float] = None, roughness: Optional[float] = None,
                     multiple_scattering: Optional[bool] = None, shadowing: Optional[str] = None) -> Material:
    """Rough interface (Walter et al. 2007): the ``dielectric`` parameters plus ``distribution``
    (``"ggx"`` or ``"beckmann"``), one of ``alpha`` / ``alpha_u`` + ``alpha_v`` / ``roughness``,
    ``multiple_scattering`` (Kulla–Conty energy compensation, GGX only) and ``shadowing``.

    docs/scene-format.md, ``### rough_dielectric``.
    """
    return _make("rough_dielectric", dict(int_ior=int_ior, ext_ior=ext_ior, specular_reflectance=specular_reflectance,
                                          specular_transmittance=specular_transmittance, distribution=distribution,
                                          alpha=alpha, alpha_u=alpha_u, alpha_v=alpha_v, roughness=roughness,
                                          multiple_scattering=multiple_scattering, shadowing=shadowing))


@_with_surface_keys
def thin_dielectric(int_ior: Optional[IOR] = None, *, ext_ior: Optional[IOR] = None,
                    specular_reflectance: Optional[Colour] = None,
                    specular_transmittance: Optional[Colour] = None) -> Material:
    """A thin slab (window pane): the ``dielectric`` parameters; light passes straight through.

    docs/scene-format.md, ``### thin_dielectric``.
    """
    return _make("thin_dielectric", dict(int_ior=int_ior, ext_ior=ext_ior, specular_reflectance=specular_reflectance,
                                         specular_transmittance=specular_transmittance))


@_with_surface_keys
def plastic(diffuse_reflectance: Optional[Colour] = None, *, specular_reflectance: Optional[Colour] = None,
            int_ior: Optional[IOR] = None, ext_ior: Optional[IOR] = None,
            variant: Optional[str] = None) -> Material:
    """A smooth dielectric coat over a Lambertian base. ``variant``: ``"coupled"`` (default,
    energy-conserving), ``"linear"`` (Mitsuba's default plastic) or ``"sum"``.

    docs/scene-format.md, ``### plastic``.
    """
    return _make("plastic", dict(diffuse_reflectance=diffuse_reflectance, specular_reflectance=specular_reflectance,
                                 int_ior=int_ior, ext_ior=ext_ior, variant=variant))


@_with_surface_keys
def rough_plastic(diffuse_reflectance: Optional[Colour] = None, *, specular_reflectance: Optional[Colour] = None,
                  int_ior: Optional[IOR] = None, ext_ior: Optional[IOR] = None, variant: Optional[str] = None,
                  distribution: Optional[str] = None, alpha: Optional[float] = None,
                  alpha_u: Optional[float] = None, alpha_v: Optional[float] = None,
                  roughness: Optional[float] = None, shadowing: Optional[str] = None,
                  coat_transmittance: Optional[str] = None) -> Material:
    """``plastic`` with a rough coat: the ``plastic`` parameters plus ``distribution``, one of
    ``alpha`` / ``alpha_u`` + ``alpha_v`` / ``roughness``, ``shadowing`` and ``coat_transmittance``
    (``"smooth"`` default, ``"rough"``: the rough coat's tabulated transmittance).

    docs/scene-format.md, ``### rough_plastic``.
    """
    return _make("rough_plastic", dict(diffuse_reflectance=diffuse_reflectance,
                                       specular_reflectance=specular_reflectance, int_ior=int_ior, ext_ior=ext_ior,
                                       variant=variant, distribution=distribution, alpha=alpha, alpha_u=alpha_u,
                                       alpha_v=alpha_v, roughness=roughness, shadowing=shadowing,
                                       coat_transmittance=coat_transmittance))


@_with_surface_keys
def principled(base_color: Optional[Colour] = None, *, variant: Optional[str] = None,
               metallic: Optional[float] = None, roughness: Optional[float] = None,
               specular: Optional[float] = None, specular_tint: Optional[float] = None,
               sheen: Optional[float] = None, sheen_tint: Optional[float] = None,
               clearcoat: Optional[float] = None, clearcoat_gloss: Optional[float] = None,
               anisotropic: Optional[float] = None, specular_transmission: Optional[float] = None,
               eta: Optional[float] = None, flatness: Optional[float] = None, thin: Optional[bool] = None,
               diffuse_transmission: Optional[float] = None) -> Material:
    """Disney principled model: ``variant="2012"`` (default) is the Burley 2012 BRDF, reflection
    only; ``variant="2015"`` the Burley 2015 BSDF (as Mitsuba 3's ``principled``) with
    ``specular_transmission``, ``eta`` (instead of ``specular``), ``flatness`` and a ``thin`` sheet
    mode with ``diffuse_transmission``. Scalars in [0, 1] (``diffuse_transmission`` in [0, 2]).

    docs/scene-format.md, ``### principled``.
    """
    return _make("principled", dict(base_color=base_color, variant=variant, metallic=metallic, roughness=roughness,
                                    specular=specular, specular_tint=specular_tint, sheen=sheen,
                                    sheen_tint=sheen_tint, clearcoat=clearcoat, clearcoat_gloss=clearcoat_gloss,
                                    anisotropic=anisotropic, specular_transmission=specular_transmission, eta=eta,
                                    flatness=flatness, thin=thin, diffuse_transmission=diffuse_transmission))


@_with_surface_keys
def subsurface(albedo: Optional[Colour] = None, *, mfp: Optional[Colour] = None, model: Optional[str] = None,
               sigma_a: Optional[Colour] = None, sigma_s: Optional[Colour] = None, scale: Optional[float] = None,
               g: Optional[float] = None, int_ior: Optional[IOR] = None, ext_ior: Optional[IOR] = None,
               distribution: Optional[str] = None, alpha: Optional[float] = None,
               alpha_u: Optional[float] = None, alpha_v: Optional[float] = None,
               roughness: Optional[float] = None, shadowing: Optional[str] = None) -> Material:
    """A translucent body (skin, marble, milk, wax): a dielectric boundary over a scattering
    interior, given by a diffuse colour ``albedo`` and mean free path ``mfp``, or by ``sigma_a`` /
    ``sigma_s`` (× ``scale``), with anisotropy ``g``. ``model``: ``"auto"`` (default: per object,
    the simplest model accurate enough), ``"dipole"``, ``"better_dipole"``, ``"random_walk"`` or
    ``"coated"``. A roughness key makes the boundary rough.

    docs/scene-format.md, ``### subsurface``; docs/subsurface.md.
    """
    return _make("subsurface", dict(albedo=albedo, mfp=mfp, model=model, sigma_a=sigma_a, sigma_s=sigma_s,
                                    scale=scale, g=g, int_ior=int_ior, ext_ior=ext_ior, distribution=distribution,
                                    alpha=alpha, alpha_u=alpha_u, alpha_v=alpha_v, roughness=roughness,
                                    shadowing=shadowing))
