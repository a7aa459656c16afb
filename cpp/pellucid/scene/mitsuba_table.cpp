// The importer's table of Mitsuba 3 plugins and parameters (scene/mitsuba_table.h). Each mapping
// and each difference in definition is described in docs/mitsuba-import.md.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/scene/mitsuba_table.h"

namespace pellucid {
namespace {
constexpr MitsubaParamUse kConverted = MitsubaParamUse::converted;
constexpr MitsubaParamUse kIgnored = MitsubaParamUse::ignored;

MitsubaParam ignored(const char* name) { return {name, "ignored", kIgnored}; }

std::vector<MitsubaPlugin> make_table() {
    const MitsubaParam to_world{"to_world", "to_world"}, flip_normals{"flip_normals", "flip_normals"};
    const MitsubaParam int_ior{"int_ior", "int_ior"}, ext_ior{"ext_ior", "ext_ior"};
    const MitsubaParam distribution{"distribution", "distribution"}, alpha{"alpha", "alpha"};
    const MitsubaParam alpha_u{"alpha_u", "alpha_u"}, alpha_v{"alpha_v", "alpha_v"};
    const MitsubaParam material{"material", "material"}, eta{"eta", "eta"}, k{"k", "k"};
    const MitsubaParam spec_refl{"specular_reflectance", "specular_reflectance"};
    const MitsubaParam spec_trans{"specular_transmittance", "specular_transmittance"};
    const MitsubaParam diffuse_refl{"diffuse_reflectance", "diffuse_reflectance"};
    const MitsubaParam sample_count{"sample_count", "sample_count"}, seed{"seed", "seed"};
    const MitsubaParam depth{"max_depth", "max_depth"}, rr_depth{"rr_depth", "rr_depth"};
    // nonlinear selects our plastic variant: false (Mitsuba's default) "linear", true "coupled".
    const MitsubaParam nonlinear{"nonlinear", "variant", kConverted};
    const MitsubaParam sobol_jitter = ignored("jitter"), sobol_dimension = ignored("dimension");
    // Media attached to a shape (docs/media.md): a named <ref> to a medium, or a nested <medium>
    // with that name. An open disk can only sit in a medium, not bound one.
    const MitsubaParam interior{"interior", "interior"}, exterior{"exterior", "exterior"};
    return {
        // ---- bsdfs
        {"bsdf", "diffuse", "lambertian", {{"reflectance", "reflectance"}}},
        // alpha is an RMS slope; Oren-Nayar's sigma (degrees) = alpha / sqrt(2) in radians.
        {"bsdf", "roughdiffuse", "oren_nayar",
         {{"reflectance", "reflectance"}, {"alpha", "sigma", kConverted}, ignored("use_fast_approx")}},
        {"bsdf", "conductor", "conductor", {material, eta, k, spec_refl}},
        {"bsdf", "roughconductor", "rough_conductor",
         {material, eta, k, spec_refl, distribution, alpha, alpha_u, alpha_v, ignored("sample_visible")}},
        {"bsdf", "dielectric", "dielectric", {int_ior, ext_ior, spec_refl, spec_trans}},
        {"bsdf", "roughdielectric", "rough_dielectric",
         {int_ior, ext_ior, spec_refl, spec_trans, distribution, alpha, alpha_u, alpha_v, ignored("sample_visible")}},
        {"bsdf", "thindielectric", "thin_dielectric", {int_ior, ext_ior, spec_refl, spec_trans}},
        {"bsdf", "plastic", "plastic",
         {int_ior, ext_ior, diffuse_refl, spec_refl, nonlinear, ignored("sample_visible")}},
        {"bsdf", "roughplastic", "rough_plastic",
         {int_ior, ext_ior, diffuse_refl, spec_refl, distribution, alpha, nonlinear, ignored("sample_visible")}},
        // principled and principledthin: our principled, variant "2015" (principledthin with thin
        // true). Sampling rates change only the noise.
        {"bsdf", "principled", "principled",
         {{"base_color", "base_color"}, {"roughness", "roughness"}, {"anisotropic", "anisotropic"},
          {"spec_trans", "specular_transmission"}, {"eta", "eta"}, {"spec_tint", "specular_tint"},
          {"sheen", "sheen"}, {"sheen_tint", "sheen_tint"}, {"flatness", "flatness"}, {"metallic", "metallic"},
          {"specular", "specular"}, {"clearcoat", "clearcoat"}, {"clearcoat_gloss", "clearcoat_gloss"},
          ignored("diffuse_reflectance_sampling_rate"), ignored("main_specular_sampling_rate"),
          ignored("clearcoat_sampling_rate")}},
        {"bsdf", "principledthin", "principled",
         {{"base_color", "base_color"}, {"roughness", "roughness"}, {"anisotropic", "anisotropic"},
          {"spec_trans", "specular_transmission"}, {"eta", "eta"}, {"spec_tint", "specular_tint"},
          {"sheen", "sheen"}, {"sheen_tint", "sheen_tint"}, {"flatness", "flatness"},
          {"diff_trans", "diffuse_transmission"}, ignored("diffuse_reflectance_sampling_rate"),
          ignored("specular_reflectance_sampling_rate"), ignored("specular_transmittance_sampling_rate"),
          ignored("diffuse_transmittance_sampling_rate")}},
        {"bsdf", "twosided", "", {}},
        // null: an index-matched boundary with no surface, bounding media only.
        {"bsdf", "null", "null", {}},
        // bumpmap takes its height texture under any name (or none); flip_invalid_normals false only
        // warns (we always correct such normals).
        {"bsdf", "bumpmap", "bump_map",
         {{"scale", "bump_scale"}, {"use_shadowing_function", "terminator_softening", kConverted},
          ignored("flip_invalid_normals")}},
        {"bsdf", "normalmap", "normal_map",
         {{"normalmap", "normal_map"}, {"use_shadowing_function", "terminator_softening", kConverted},
          ignored("flip_invalid_normals")}},
        // ---- textures
        {"texture", "bitmap", "image",
         {{"filename", "filename"}, {"filter_type", "filter"}, {"wrap_mode", "wrap_mode"}, {"to_uv", "to_uv"},
          {"raw", "color_space", kConverted}, ignored("format")}},
        {"texture", "checkerboard", "checkerboard", {{"color0", "color0"}, {"color1", "color1"}, {"to_uv", "to_uv"}}},
        // ---- shapes
        {"shape", "obj", "obj",
         {{"filename", "filename"}, {"face_normals", "face_normals"}, {"flip_tex_coords", "flip_tex_coords"},
          flip_normals, to_world, interior, exterior}},
        {"shape", "ply", "ply",
         {{"filename", "filename"}, {"face_normals", "face_normals"}, flip_normals, to_world, interior, exterior}},
        {"shape", "sphere", "sphere",
         {{"center", "center"}, {"radius", "radius"}, flip_normals, to_world, interior, exterior}},
        {"shape", "rectangle", "rectangle", {flip_normals, to_world, interior, exterior}},
        {"shape", "cube", "cube", {flip_normals, to_world, interior, exterior}},
        {"shape", "disk", "disk", {flip_normals, to_world, exterior}},
        // ---- media and phase functions (docs/media.md). sigma_a / sigma_s are Mitsuba 0.6's
        // names (Mitsuba 3 takes sigma_t and albedo); our homogeneous takes either pair.
        {"medium", "homogeneous", "homogeneous",
         {{"sigma_t", "sigma_t"}, {"albedo", "albedo"}, {"scale", "scale"}, {"sigma_a", "sigma_a"},
          {"sigma_s", "sigma_s"}}},
        {"phase", "isotropic", "isotropic", {}},
        {"phase", "hg", "hg", {{"g", "g"}}},
        // ---- emitters
        {"emitter", "area", "area", {{"radiance", "radiance"}}},
        {"emitter", "point", "point", {{"position", "position"}, {"intensity", "intensity"}, to_world}},
        {"emitter", "spot", "spot",
         {{"intensity", "intensity"}, {"cutoff_angle", "cutoff_angle"}, {"beam_width", "beam_width"}, to_world}},
        {"emitter", "directional", "directional", {{"irradiance", "irradiance"}, {"direction", "direction"}, to_world}},
        {"emitter", "constant", "constant", {{"radiance", "radiance"}}},
        {"emitter", "envmap", "envmap",
         {{"filename", "filename"}, {"scale", "scale"}, to_world, ignored("mis_compensation")}},
        // ---- sensor, film, reconstruction filters
        {"sensor", "perspective", "perspective",
         {{"fov", "fov"}, {"fov_axis", "fov_axis"}, to_world, ignored("near_clip"), ignored("far_clip")}},
        {"film", "hdrfilm", "film",
         {{"width", "width"}, {"height", "height"}, ignored("pixel_format"), ignored("component_format"),
          ignored("file_format"), ignored("banner"),
          // sample_border selects the reconstruction: false splatting, true filter sampling.
          {"sample_border", "reconstruction", kConverted}}},
        {"rfilter", "box", "box", {{"radius", "radius"}}},
        {"rfilter", "tent", "tent", {{"radius", "radius"}}},
        {"rfilter", "gaussian", "gaussian", {{"stddev", "stddev"}}},
        // ---- samplers: Mitsuba's stratified and low-discrepancy samplers become our Owen-scrambled
        // Sobol sampler, a different point set with the same expectation (docs/mitsuba-import.md).
        {"sampler", "independent", "independent", {sample_count, seed}},
        {"sampler", "stratified", "sobol", {sample_count, seed, sobol_jitter, sobol_dimension}},
        {"sampler", "multijitter", "sobol", {sample_count, seed, sobol_jitter, sobol_dimension}},
        {"sampler", "orthogonal", "sobol", {sample_count, seed, sobol_jitter, sobol_dimension}},
        {"sampler", "ldsampler", "sobol", {sample_count, seed, sobol_jitter, sobol_dimension}},
        {"sampler", "low_discrepancy", "sobol", {sample_count, seed, sobol_jitter, sobol_dimension}},
        // ---- integrators: volpath is our path integrator, which renders media
        {"integrator", "path", "path", {depth, rr_depth}},
        {"integrator", "volpath", "path", {depth, rr_depth}},
    };
}
}  // namespace

const std::vector<MitsubaPlugin>& mitsuba_import_table() {
    static const std::vector<MitsubaPlugin> table = make_table();
    return table;
}

const MitsubaPlugin* find_mitsuba_plugin(const std::string& kind, const std::string& plugin) {
    for (const MitsubaPlugin& p : mitsuba_import_table())
        if (kind == p.kind && plugin == p.plugin) return &p;
    return nullptr;
}

std::string mitsuba_known_plugins(const std::string& kind) {
    std::string out;
    for (const MitsubaPlugin& p : mitsuba_import_table())
        if (kind == p.kind) out += (out.empty() ? "" : ", ") + std::string(p.plugin);
    return out;
}
}  // namespace pellucid
