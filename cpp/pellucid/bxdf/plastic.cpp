// Smooth and rough plastic, and the rough coat's transmittance table.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/bxdf/plastic.h"

#include <algorithm>
#include <map>
#include <memory>
#include <mutex>

#include "pellucid/bxdf/quadrature.h"
#include "pellucid/sampling/warp.h"

namespace pellucid {

std::string to_string(PlasticVariant v) {
    switch (v) {
        case PlasticVariant::Coupled: return "coupled";
        case PlasticVariant::Linear: return "linear";
        case PlasticVariant::Sum: break;
    }
    return "sum";
}
std::string to_string(CoatTransmittance c) { return c == CoatTransmittance::Rough ? "rough" : "smooth"; }

// ---------------------------------------------------------------------------------------------
// RoughCoatTable
bool RoughCoatTable::Key::operator<(const Key& o) const {
    if (kind != o.kind) return kind < o.kind;
    if (shadowing != o.shadowing) return shadowing < o.shadowing;
    if (alpha_x != o.alpha_x) return alpha_x < o.alpha_x;
    if (alpha_y != o.alpha_y) return alpha_y < o.alpha_y;
    return eta < o.eta;
}

namespace {
// ∫∫_[0,1]² f(u) du by the 32 × 32 Gauss–Legendre product rule.
template <class F>
double integrate_unit_square(F&& f) {
    const GaussLegendre32& q = gauss_legendre_32();
    double sum = 0.0;
    for (int i = 0; i < 32; ++i)
        for (int j = 0; j < 32; ++j)
            sum += q.w[i] * q.w[j] * f(Vec2f(float(0.5 + 0.5 * q.x[i]), float(0.5 + 0.5 * q.x[j])));
    return 0.25 * sum;
}

// Single-scattering energy that a rough interface of relative IOR eta (the far side's IOR over the
// near side's) sends from the direction at cos θ = mu, azimuth phi, into the far side (transmit =
// true) or back to the near side, as an expectation over visible normals wm ~ D_wo (Heitz 2018,
// JCGT 7(4), §1):
//   ∫ D_wo(wm) F' G2(wo, w)/G1(wo) dwm, F' = 1 − F(wo·wm) or F(wo·wm), w the refracted or
// reflected direction (0 where it leaves on the wrong side, and on total internal reflection).
template <class D>
double interface_energy_at(const D& d, double mu, double phi, float eta, bool transmit) {
    mu = std::max(1e-6, std::min(1.0, mu));
    double s = std::sqrt(std::max(0.0, 1.0 - mu * mu));
    Vec3f wo(float(s * std::cos(phi)), float(s * std::sin(phi)), float(mu));
    float g1 = d.G1(wo);
    if (!(g1 > 0.f)) return 0.0;
    return integrate_unit_square([&](const Vec2f& u) {
        Vec3f wm = d.sample_visible(wo, u);
        double F = fresnel_dielectric_d(dot(wo, wm), eta);
        if (transmit) {
            Vec3f wt;
            float etap;
            if (F >= 1.0 || !refract(wo, wm, eta, &etap, &wt) || !(wt.z < 0.f)) return 0.0;
            return (1.0 - F) * double(d.G(wo, wt)) / g1;
        }
        Vec3f wr = reflect(wo, wm);
        return wr.z > 0.f ? F * double(d.G(wo, wr)) / g1 : 0.0;
    });
}
// The same, averaged over the azimuth of wo: the table depends on θ only. An isotropic distribution
// needs one azimuth; an anisotropic one is averaged with the midpoint rule at 8 azimuths in
// [0, π/2] (D is symmetric under x → −x and y → −y, and the integrand is smooth and periodic in φ).
template <class D>
double interface_energy(const D& d, double mu, float eta, bool transmit) {
    if (d.alpha_x() == d.alpha_y()) return interface_energy_at(d, mu, 0.0, eta, transmit);
    constexpr int kPhi = 8;
    double sum = 0.0;
    for (int k = 0; k < kPhi; ++k) sum += interface_energy_at(d, mu, 0.5 * M_PI * (k + 0.5) / kPhi, eta, transmit);
    return sum / kPhi;
}
}  // namespace

template <class D>
RoughCoatTable RoughCoatTable::compute(const D& d, float eta) {
    RoughCoatTable t;
    t.m_key = key_of(d, eta);
    for (int j = 0; j < kSize; ++j)
        t.m_t[j] = float(interface_energy(d, double(j) / (kSize - 1), eta, true));
    // R̄ = 2∫₀¹ R_int(μ) μ dμ, seen from inside (relative IOR 1/η). Split at the smooth interior's
    // critical cosine μc = √(1 − 1/η²) (η > 1), and on [μc, 1] substitute μ = μc + (1 − μc) s²,
    // which removes the √(μ − μc) edge R_int has there as α → 0 (as fresnel_dielectric_average).
    const float eta_in = 1.f / eta;
    double mu_c = eta > 1.f ? std::sqrt(std::max(0.0, 1.0 - 1.0 / (double(eta) * eta))) : 0.0;
    double w = 1.0 - mu_c;
    double rbar = mu_c > 0.0 ? integrate_gauss_legendre(
                                   [&](double mu) { return interface_energy(d, mu, eta_in, false) * mu; }, 0.0, mu_c)
                             : 0.0;
    rbar += integrate_gauss_legendre(
        [&](double s) {
            double mu = mu_c + w * s * s;
            return interface_energy(d, mu, eta_in, false) * mu * 2.0 * w * s;
        },
        0.0, 1.0);
    t.m_rbar = float(std::min(1.0, 2.0 * rbar));
    return t;
}

template <class D>
const RoughCoatTable& RoughCoatTable::get(const D& d, float eta) {
    // Process-wide, never freed (header comment): std::map nodes do not move, so the references
    // handed out stay valid. The table is computed outside the lock; a concurrent first request for
    // the same key computes it twice and keeps the first.
    static std::mutex mutex;
    static std::map<Key, std::unique_ptr<const RoughCoatTable>>* cache =
        new std::map<Key, std::unique_ptr<const RoughCoatTable>>();
    const Key key = key_of(d, eta);
    {
        std::lock_guard<std::mutex> lock(mutex);
        auto it = cache->find(key);
        if (it != cache->end()) return *it->second;
    }
    auto table = std::make_unique<const RoughCoatTable>(compute(d, eta));
    std::lock_guard<std::mutex> lock(mutex);
    auto it = cache->emplace(key, std::move(table)).first;
    return *it->second;
}

float RoughCoatTable::transmittance(float mu) const { return coat_table_lookup<float>(m_t, 0, mu); }

template const RoughCoatTable& RoughCoatTable::get<GGX>(const GGX&, float);
template const RoughCoatTable& RoughCoatTable::get<Beckmann>(const Beckmann&, float);
template RoughCoatTable RoughCoatTable::compute<GGX>(const GGX&, float);
template RoughCoatTable RoughCoatTable::compute<Beckmann>(const Beckmann&, float);

// ---------------------------------------------------------------------------------------------
// PlasticBase
PlasticBase::PlasticBase(float eta, const Spectrum& kd, const Spectrum& ks, PlasticVariant variant,
                         const RoughCoatTable* coat, const DielectricFresnelAverage* fresnel_avg)
    : m_eta(eta > 0.f && std::isfinite(eta) ? eta : 1.f), m_kd(kd), m_ks(ks), m_variant(variant),
      m_coat(variant == PlasticVariant::Sum ? nullptr : coat) {
    m_lanes.eta = m_eta;
    m_lanes.ks = m_ks;
    m_lanes.ks_avg = m_ks.average();
    m_lanes.kd_avg = m_kd.average();
    m_lanes.coat = m_coat ? 0.f : PlasticBaseT<float>::kSmoothCoat;
    m_lanes.tables = m_coat ? m_coat->values() : nullptr;
    if (m_variant == PlasticVariant::Sum) {
        m_lanes.scale = m_kd;
        m_lanes.coat = PlasticBaseT<float>::kSumCoat;
        return;
    }
    m_rbar = m_coat ? m_coat->internal_reflectance()
                    : 1.f - (1.f - fresnel_average(m_eta, fresnel_avg)) / (m_eta * m_eta);
    for (int c = 0; c < 3; ++c) m_lanes.scale[c] = plastic_diffuse_scale<float>(m_kd[c], m_eta, m_rbar, m_variant);
}

float PlasticBase::transmittance(float mu) const {
    return m_coat ? m_coat->transmittance(mu) : 1.f - fresnel_dielectric(mu, m_eta);
}

Spectrum PlasticBase::diffuse(float cos_o, float cos_i) const {
    return m_lanes.diffuse(m_lanes.transmittance(cos_o), cos_i);
}

float PlasticBase::coat_probability(float cos_o) const { return m_lanes.coat_probability(cos_o); }

void plastic_packet_params(const PlasticBase& base, const GGXT<float>* d, std::vector<float>* tables, float* q,
                           const float* coat_offset) {
    const PlasticBaseT<float>& b = base.lanes();
    float coat = b.coat;
    if (base.coat_table() && coat_offset) {
        coat = *coat_offset;  // (the caller found the table among the tables already)
    } else if (const RoughCoatTable* t = base.coat_table()) {
        const float* v = t->values();
        size_t at = 0;
        while (at < tables->size() && !std::equal(v, v + kCoatTableSize, tables->data() + at)) at += kCoatTableSize;
        if (at == tables->size()) tables->insert(tables->end(), v, v + kCoatTableSize);
        coat = float(at);
    }
    q[0] = b.eta;
    for (int c = 0; c < 3; ++c) q[1 + c] = b.scale[c], q[4 + c] = b.ks[c];
    q[7] = b.ks_avg, q[8] = b.kd_avg;
    q[9] = d ? d->ax : 0.f, q[10] = d ? (d->separable ? -d->ay : d->ay) : 0.f;
    q[kPlasticCoatParam] = coat;
}

std::string PlasticBase::params() const {
    std::string s = "eta=" + std::to_string(m_eta) + ", diffuse_reflectance=" + m_kd.to_string() +
                    ", specular_reflectance=" + m_ks.to_string() + ", variant=" + pellucid::to_string(m_variant);
    return m_coat ? s + ", coat_transmittance=rough" : s;
}

// ---------------------------------------------------------------------------------------------
BxDFFlags SmoothPlastic::flags() const {
    BxDFFlags f = BxDFFlags::None;
    if (!m_base.ks().is_black() && m_base.eta() != 1.f) f |= BxDFFlags::SpecularReflection;
    if (!m_base.diffuse(1.f, 1.f).is_black()) f |= BxDFFlags::DiffuseReflection;
    return f;
}

// ---------------------------------------------------------------------------------------------
template <class D>
BxDFFlags RoughPlastic<D>::flags() const {
    if (smooth()) return SmoothPlastic(m_base).flags();
    BxDFFlags f = BxDFFlags::None;
    if (!m_base.ks().is_black() && m_base.eta() != 1.f) f |= BxDFFlags::GlossyReflection;
    if (!m_base.diffuse(1.f, 1.f).is_black()) f |= BxDFFlags::DiffuseReflection;
    return f;
}

template class RoughPlastic<GGX>;
template class RoughPlastic<Beckmann>;
}  // namespace pellucid
