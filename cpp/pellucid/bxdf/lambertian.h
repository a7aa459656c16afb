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

class Lambertian {
public:
    explicit Lambertian(const Spectrum& reflectance) : m_r(reflectance) {}

    Spectrum eval(const BxDFContext&, const Vec3f& wo, const Vec3f& wi) const {
        if (!same_hemisphere(wo, wi)) return Spectrum(0.f);
        return m_r * (kInvPi * abs_cos_theta(wi));
    }
    float pdf(const BxDFContext& ctx, const Vec3f& wo, const Vec3f& wi) const {
        if (!has_flag(ctx.allowed, BxDFFlags::DiffuseReflection) || !same_hemisphere(wo, wi))
            return 0.f;
        return square_to_cosine_hemisphere_pdf(Vec3f(wi.x, wi.y, std::fabs(wi.z)));
    }
    std::optional<BxDFSample> sample(const BxDFContext& ctx, const Vec3f& wo, float /*u_lobe*/,
                                     const Vec2f& u) const {
        if (!has_flag(ctx.allowed, BxDFFlags::Reflection) || wo.z == 0.f) return std::nullopt;
        Vec3f wi = square_to_cosine_hemisphere(u);
        if (wo.z < 0.f) wi.z = -wi.z;
        float pdf = square_to_cosine_hemisphere_pdf(Vec3f(wi.x, wi.y, std::fabs(wi.z)));
        if (!(pdf > 0.f)) return std::nullopt;
        BxDFSample s;
        s.wi = wi;
        s.weight = m_r;  // (ρ/π)·cos θ / (cos θ/π)
        s.pdf = pdf;
        s.lobe = BxDFFlags::DiffuseReflection;
        return s;
    }
    BxDFFlags flags() const {
        return m_r.is_black() ? BxDFFlags::None : BxDFFlags::DiffuseReflection;
    }
    /// Hemispherical albedo, used for AOVs and for "model no more than needed" decisions.
    Spectrum albedo() const { return m_r; }
    std::string to_string() const { return "Lambertian[reflectance=" + m_r.to_string() + "]"; }

private:
    Spectrum m_r;
};
}  // namespace pellucid
