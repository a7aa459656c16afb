// SPDX-License-Identifier: Apache-2.0
#include "pellucid/bssrdf/separable.h"

#include <algorithm>
#include <cmath>

#include "pellucid/bxdf/fresnel.h"
#include "pellucid/math/frame.h"
#include "pellucid/sampling/warp.h"
#include "pellucid/scene/scene.h"

namespace pellucid {

void subsurface_coefficients(const SubsurfaceParams& p, const TexEval& tex, bssrdf::Diffusion model, Spectrum* sigma_a,
                             Spectrum* sigma_s) {
    if (!p.from_albedo) {
        *sigma_a = tex(p.sigma_a) * p.scale;
        *sigma_s = tex(p.sigma_s) * p.scale;
        return;
    }
    // The reduced coefficients come from the inversion; σs = σ's/(1 − g).
    const float one_minus_g = 1.f - tex(p.g), eta = relative_eta(p.boundary, tex);
    const Spectrum albedo = tex(p.albedo), mfp_rgb = tex(p.mfp);
    for (int c = 0; c < 3; ++c) {
        const float mfp = mfp_rgb[c];
        float sa = 0.f, ss = 0.f;
        if (albedo[c] >= 1.f) {
            ss = 1.f / mfp;  // lossless: σ't = σ's = 1/mfp
        } else if (!bssrdf::from_diffuse(model, albedo[c], mfp, 0.f, eta, &sa, &ss)) {
            sa = 1.f / mfp;  // albedo 0 (or below the model's range): an absorber
            ss = 0.f;
        }
        (*sigma_a)[c] = sa;
        (*sigma_s)[c] = ss / one_minus_g;
    }
}

SeparableBSSRDF make_separable_bssrdf(const SubsurfaceParams& p, const TexEval& tex, bssrdf::Diffusion model,
                                      uint32_t shape) {
    SeparableBSSRDF b;
    Spectrum sa, ss;
    subsurface_coefficients(p, tex, model, &sa, &ss);
    const float g = tex(p.g);
    b.eta = relative_eta(p.boundary, tex);
    b.exit_norm = bssrdf::exit_lobe_norm(b.eta);
    const bssrdf::BoundaryMoments moments = bssrdf::boundary_moments(b.eta);
    for (int c = 0; c < 3; ++c) {
        b.profile[c] = bssrdf::Profile::make(model, sa[c], ss[c], g, moments);
        b.r_max[c] = b.profile[c].r_max();
    }
    b.shape = shape;
    b.model = model;
    return b;
}

SeparableBSSRDF bssrdf_at(const Scene& scene, const SeparableBSSRDF& b, const SurfaceInteraction& si) {
    const MaterialTextures& mt = scene.material_textures[si.material_id];
    const auto* m = std::get_if<SubsurfaceParams>(&scene.materials[si.material_id]);
    if (!mt.has_textured_params() || !m) return b;
    const TextureEvalContext ctx = texture_eval_context(si);
    return make_separable_bssrdf(*m, TexEval(scene.textures, ctx), b.model, b.shape);
}

Spectrum SeparableBSSRDF::sp(float r) const {
    return Spectrum(profile[0].eval(r), profile[1].eval(r), profile[2].eval(r));
}
Spectrum SeparableBSSRDF::total() const {
    return Spectrum(profile[0].total(), profile[1].total(), profile[2].total());
}

Spectrum SeparableBSSRDF::exit_eval(const Vec3f& wi, float* pdf) const {
    if (!(wi.z > 0.f)) {
        *pdf = 0.f;
        return Spectrum(0.f);
    }
    *pdf = wi.z * kInvPi;
    return Spectrum((1.f - fresnel_dielectric(wi.z, eta)) / (exit_norm * kPi) * wi.z);
}

bool SeparableBSSRDF::exit_sample(const Vec2f& u, BxDFSample* out) const {
    const Vec3f wi = square_to_cosine_hemisphere(u);
    if (!(wi.z > 0.f)) return false;
    out->wi = wi;
    out->pdf = wi.z * kInvPi;
    out->weight = Spectrum((1.f - fresnel_dielectric(wi.z, eta)) / exit_norm);
    out->eta = 1.f;
    out->lobe = BxDFFlags::DiffuseReflection;
    return out->pdf > 0.f;
}

namespace {
constexpr float kAxisProb[3] = {0.25f, 0.25f, 0.5f};  // s, t, n

/// The mixture density of an exit point at offset d from po with normal n (both in the entry's
/// shading frame), per unit area, before the division by the number of hits.
float mixture_pdf(const SeparableBSSRDF& b, const Vec3f& d, const Vec3f& n) {
    const float dist2 = dot(d, d);
    const float r_axis[3] = {std::sqrt(d.y * d.y + d.z * d.z), std::sqrt(d.z * d.z + d.x * d.x),
                             std::sqrt(d.x * d.x + d.y * d.y)};
    const float n_axis[3] = {std::fabs(n.x), std::fabs(n.y), std::fabs(n.z)};
    float pdf = 0.f;
    for (int a = 0; a < 3; ++a)
        for (int c = 0; c < 3; ++c) {
            // The chord of channel c covers the points within r_max[c] of po.
            if (!(dist2 < b.r_max[c] * b.r_max[c])) continue;
            pdf += kAxisProb[a] * (1.f / 3.f) * b.profile[c].pdf(r_axis[a]) * n_axis[a];
        }
    return pdf;
}
}  // namespace

float probe_pdf(const SeparableBSSRDF& b, const SurfaceInteraction& entry, const Point3f& pi, const Normal3f& ni) {
    const Frame& f = entry.shading;
    return mixture_pdf(b, f.to_local(pi - entry.p), f.to_local(ni));
}

bool sample_probe(const Scene& scene, const SeparableBSSRDF& b, const SurfaceInteraction& entry, float u_axis,
                  const Vec2f& u, float u_hit, SurfaceInteraction* exit, Spectrum* weight) {
    const Frame& f = entry.shading;
    // The axis, then the channel, from one number (each choice rescales it back to [0, 1)).
    Vec3f vx, vy, axis;
    if (u_axis < 0.5f) {
        axis = f.n, vx = f.s, vy = f.t;
        u_axis *= 2.f;
    } else if (u_axis < 0.75f) {
        axis = f.s, vx = f.t, vy = f.n;
        u_axis = (u_axis - 0.5f) * 4.f;
    } else {
        axis = f.t, vx = f.n, vy = f.s;
        u_axis = (u_axis - 0.75f) * 4.f;
    }
    const int ch = std::min(int(u_axis * 3.f), 2);
    const float r = b.profile[ch].sample(u.x);
    const float r_max = b.r_max[ch];
    if (!(r >= 0.f) || !(r < r_max)) return false;
    const float phi = 2.f * kPi * u.y;
    const float half = std::sqrt(std::max(0.f, r_max * r_max - r * r));
    const Point3f start = entry.p + r * (std::cos(phi) * vx + std::sin(phi) * vy) - half * axis;
    // Every surface of this shape along the chord; at most kMaxHits are kept (a chord through a
    // mesh crosses it a few times; more than this many crossings within r_max is not a closed
    // translucent body's geometry).
    constexpr int kMaxHits = 8;
    SurfaceInteraction hits[kMaxHits];
    int n = 0;
    Point3f o = start;
    float left = 2.f * half;
    for (int guard = 0; guard < 64 && left > 0.f; ++guard) {
        SurfaceInteraction h;
        if (!scene.intersect(Ray{o, axis, left}, h)) break;
        left -= h.t;
        o = h.spawn_ray(axis).o;
        left -= length(o - h.p);
        if (h.shape_id == b.shape && n < kMaxHits) hits[n++] = h;
    }
    if (n == 0) return false;
    const int k = std::min(int(u_hit * float(n)), n - 1);
    SurfaceInteraction& x = hits[k];
    const float pdf = mixture_pdf(b, f.to_local(x.p - entry.p), f.to_local(x.ng)) / float(n);
    if (!(pdf > 0.f)) return false;
    *weight = b.sp(length(x.p - entry.p)) / pdf;
    // The exit scatters to the outside: the side the geometric normal points to.
    if (dot(x.shading.n, x.ng) < 0.f) x.shading = Frame(-x.shading.s, x.shading.t, -x.shading.n);
    x.wo = x.ng;
    *exit = x;
    return weight->is_finite() && !weight->is_black();
}
}  // namespace pellucid
