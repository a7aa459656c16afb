// Lambertian (ideal diffuse) reflection: f = ρ/π.
// SPDX-License-Identifier: Apache-2.0
//
// | parameter   | type     | default | meaning                                     |
// |-------------|----------|---------|---------------------------------------------|
// | reflectance | spectrum | 0.5     | hemispherical albedo ρ ∈ [0, 1] per channel |
// JSON: {"type": "lambertian", "reflectance": [0.8, 0.2, 0.2]}
#pragma once
#include <optional>
#include <string>

#include "pellucid/bxdf/bxdf_types.h"
#include "pellucid/math/spherical.h"
#include "pellucid/sampling/warp.h"

namespace pellucid {

/// The model over a lane type F (simd/lane.h): one reflectance per lane. Lambertian (the variant's
/// alternative) is its float instantiation behind the scalar BxDF API.
template <class F>
struct LambertianT {
    RGB<F> r;

    RGB<F> eval(const BxDFContext&, const V3<F>& wo, const V3<F>& wi) const {
        return lane::select(wo.z * wi.z > F(0.f), r * (F(kInvPi) * lane::abs(wi.z)), RGB<F>(F(0.f)));
    }
    F pdf(const BxDFContext& ctx, const V3<F>& wo, const V3<F>& wi) const {
        if (!has_flag(ctx.allowed, BxDFFlags::DiffuseReflection)) return F(0.f);
        const F c = lane::abs(wi.z);
        return lane::select(wo.z * wi.z > F(0.f) && c > F(0.f), c * F(kInvPi), F(0.f));
    }
    /// Cosine-weighted about the normal on wo's side; weight = (ρ/π)·cos θ / (cos θ/π) = ρ.
    BxDFSampleT<F> sample(const BxDFContext& ctx, const V3<F>& wo, const F& /*u_lobe*/, const V2<F>& u) const {
        BxDFSampleT<F> s;
        s.wi = square_to_cosine_hemisphere<F>(u);
        s.wi.z = lane::select(wo.z < F(0.f), lane::neg(s.wi.z), s.wi.z);
        s.pdf = square_to_cosine_hemisphere_pdf<F>(V3<F>(s.wi.x, s.wi.y, lane::abs(s.wi.z)));
        s.valid = wo.z != F(0.f) && s.pdf > F(0.f);
        if (!has_flag(ctx.allowed, BxDFFlags::Reflection)) s.valid = MaskT<F>(false);
        s.weight = r;
        s.eta = F(1.f);
        s.lobe = IntT<F>(int32_t(BxDFFlags::DiffuseReflection));
        return s;
    }
};

class Lambertian {
public:
    explicit Lambertian(const Spectrum& reflectance) : m_lanes{reflectance} {}

    Spectrum eval(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const { return m_lanes.eval(ctx, wo, wi); }
    float pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const { return m_lanes.pdf(ctx, wo, wi); }
    std::optional<BxDFSample> sample(const BxDFContext& ctx, const Vec3f& wo, float u_lobe, const Vec2f& u) const {
        return to_optional(m_lanes.sample(ctx, wo, u_lobe, u));
    }
    BxDFFlags flags() const {
        return m_lanes.r.is_black() ? BxDFFlags::None : BxDFFlags::DiffuseReflection;
    }
    /// Hemispherical albedo, used for AOVs and for "model no more than needed" decisions.
    Spectrum albedo() const { return m_lanes.r; }
    std::string to_string() const { return "Lambertian[reflectance=" + m_lanes.r.to_string() + "]"; }

private:
    LambertianT<float> m_lanes;
};
}  // namespace pellucid
