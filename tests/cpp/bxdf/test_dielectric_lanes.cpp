// Lanes equal scalars for the rough dielectrics' packet forms (bxdf/dielectric_probe.h): on every
// lane of every SIMD target, eval, pdf and sample give exactly the bits the float instantiation
// gives for that lane's inputs (a bound of 0 ulp: the library and the probes are built without
// contraction; the half vector and Fresnel are the float function's own, called a lane at a time,
// and the rest uses only IEEE-exact lane operations). The float instantiation, built from packet
// parameters as the path tracer builds it, in turn gives the bits of the scalar BxDF API
// (RoughDielectric<GGX>, RoughDielectric<Beckmann> without multiple scattering).
//
// Cases: the property suite's rough dielectrics (bxdf_cases.h: its cases and sweeps over α and η,
// both sides of 1, both shadowing forms, anisotropic α) without Kulla–Conty compensation, one
// material per lane at random so every packet mixes GGX and Beckmann materials; lanes of other
// models and partially masked packets; directions on, near and below the horizon, at the normal,
// in the mirror direction and straight through; u at 0, 1/2 and 1 − 2⁻²⁴; both transport modes and
// reflection-only and transmission-only contexts.
//
// The half-vector step (dielectric_half_lanes, computed in double on each packet's double parts)
// and the Fresnel pair are also compared field by field on the same grid, whose directions add
// transmission pairs built at the critical angle of the denser side (±10⁻³ and ±10⁻⁶ relative,
// refracting or totally reflected), pairs whose generalised half vector faces away from one of them
// (back-facing microfacets), and pairs whose z product underflows in float; the Fresnel pair's own
// cosines are at the critical cosine (both sides, relative ±10⁻³, ±10⁻⁶, ±1 ulp), ±0, ±1, just
// outside [−1, 1], grazing and at random.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "bxdf/bxdf_cases.h"
#include "bxdf/dielectric_probe.h"
#include "pellucid/integrator/simd_target.h"
#include "pellucid/sampling/rng.h"
#include "pellucid/sampling/warp.h"
#include "support/probe_outputs.h"

using namespace pellucid;

namespace pellucid::dielectric_probe {
#ifdef PELLUCID_DIELECTRIC_PROBE_AVX512
void run_avx512(const In& in, Out& out);
#endif
#ifdef PELLUCID_DIELECTRIC_PROBE_AVX2
void run_avx2(const In& in, Out& out);
#endif
#ifdef PELLUCID_DIELECTRIC_PROBE_SSE4
void run_sse4(const In& in, Out& out);
#endif
}  // namespace pellucid::dielectric_probe

namespace {
/// The property suite's rough dielectrics that have a packet form (no multiple scattering).
std::vector<BxDF> materials() {
    std::vector<BxDF> m;
    using test::BxDFCases;
    auto add = [&](const auto& b) {
        if (b.has_lanes()) m.emplace_back(b);
    };
    for (const auto& c : BxDFCases<RoughDielectric<GGX>>::cases()) add(c.bxdf);
    for (const auto& b : BxDFCases<RoughDielectric<GGX>>::sweep()) add(b);
    for (const auto& c : BxDFCases<RoughDielectric<Beckmann>>::cases()) add(c.bxdf);
    for (const auto& b : BxDFCases<RoughDielectric<Beckmann>>::sweep()) add(b);
    m.emplace_back(RoughDielectric<GGX>(GGX(0.02f, 0.7f), 1.7f, Spectrum(0.9f, 0.5f, 0.2f), Spectrum(0.3f, 0.6f, 1.f)));
    m.emplace_back(RoughDielectric<Beckmann>(Beckmann(0.5f, 0.03f, SmithShadowing::Separable), 1.f / 1.6f,
                                             Spectrum(1.f), Spectrum(0.8f)));
    return m;
}

struct Cases {
    static constexpr int kN = 16384;
    std::vector<BxDF> mats = materials();
    std::vector<float> params;  // kRoughDielectricParams per material
    std::vector<float> q[kRoughDielectricParams], a[9], cos_i;
    std::vector<int> mat;  // -1: a lane of another model
    std::vector<int32_t> kind;
    std::unique_ptr<bool[]> active{new bool[kN]};
    int ggx = 0, beckmann = 0;
    dielectric_probe::In in;

    Cases() {
        params.resize(mats.size() * kRoughDielectricParams);
        for (size_t m = 0; m < mats.size(); ++m) {
            float* p = &params[m * kRoughDielectricParams];
            if (const auto* g = std::get_if<RoughDielectric<GGX>>(&mats[m])) {
                rough_dielectric_packet_params(g->lanes(), p);
                ++ggx;
            } else {
                rough_dielectric_packet_params(std::get<RoughDielectric<Beckmann>>(mats[m]).lanes(), p);
                ++beckmann;
            }
        }
        PCG32 rng(5, 23);
        for (auto& v : q) v.resize(kN);
        for (auto& v : a) v.resize(kN);
        mat.resize(kN);
        kind.resize(kN);
        cos_i.resize(kN);
        auto dir = [&](int i, int at) {
            const Vec3f w = square_to_uniform_sphere(Vec2f(rng.next_float(), rng.next_float()));
            for (int c = 0; c < 3; ++c) a[at + c][size_t(i)] = w[c];
        };
        const float us[] = {0.f, 0.5f, kOneMinusEpsilon, 1e-7f};
        for (int i = 0; i < kN; ++i) {
            const size_t k = size_t(i);
            mat[k] = i % 13 == 5 ? -1 : int(rng.next_u32() % uint32_t(mats.size()));
            dir(i, 0), dir(i, 3);
            float *wo[3] = {&a[0][k], &a[1][k], &a[2][k]}, *wi[3] = {&a[3][k], &a[4][k], &a[5][k]};
            switch (i % 11) {  // edge cases
                case 1: *wo[2] = 0.f; break;                                                 // wo on the horizon
                case 2: *wi[2] = 1e-7f; break;                                               // wi grazing
                case 3: *wo[0] = -*wi[0], *wo[1] = -*wi[1], *wo[2] = *wi[2]; break;          // the mirror direction
                case 4: *wo[0] = *wo[1] = 0.f, *wo[2] = 1.f; break;                          // wo at the normal
                case 5: *wi[2] = -std::fabs(*wi[2]), *wo[2] = std::fabs(*wo[2]); break;      // a transmission pair
                case 6: *wo[2] = -std::fabs(*wo[2]), *wi[2] = std::fabs(*wi[2]); break;      // one from inside
                case 7: *wo[2] = 1e-7f; break;                                               // wo grazing
                case 8: *wi[0] = -*wo[0], *wi[1] = -*wo[1], *wi[2] = -*wo[2]; break;         // straight through
                case 9: *wo[2] = -1e-6f, *wi[2] = std::fabs(*wi[2]); break;                   // grazing from inside
                default: break;
            }
            for (int c = 0; c < 3; ++c) a[6 + c][k] = i % 7 < 4 ? us[(i / 7 + c) % 4] : rng.next_float();
            for (int p = 0; p < kRoughDielectricParams; ++p)
                q[p][k] = mat[k] >= 0 ? params[size_t(mat[k]) * kRoughDielectricParams + size_t(p)] : 1e6f + float(p);
            // The lane's η (rough_dielectric_lanes gives other models' lanes 1.5) and the cosine
            // of the critical angle on its denser side.
            const float eta = mat[k] >= 0 ? q[0][k] : 1.5f;
            const double eta_ld = eta >= 1.f ? double(eta) : 1.0 / double(eta);
            const double crit = std::sqrt(1.0 - 1.0 / (eta_ld * eta_ld));
            const double rel[] = {-1e-3, -1e-6, 0.0, 1e-6, 1e-3};
            if (i % 11 == 10) switch ((i / 11) % 4) {  // half-vector edge cases
                    case 0: {  // a transmission pair at the critical angle of the denser side
                        const Vec3f wm = square_to_uniform_hemisphere(Vec2f(rng.next_float(), rng.next_float()));
                        const Vec3f t = normalize(cross(wm, std::fabs(wm.x) < 0.9f ? Vec3f(1, 0, 0) : Vec3f(0, 1, 0)));
                        const double c = std::min(1.0, crit * (1.0 + rel[(i / 44) % 5]));
                        const float side = eta >= 1.f ? -1.f : 1.f;  // the denser side of the interface
                        const Vec3f w = side * float(c) * wm + float(std::sqrt(1.0 - c * c)) * t;
                        float etap;
                        Vec3f wt;
                        if (!refract(w, wm, eta, &etap, &wt)) wt = reflect(w, wm);  // TIR: the mirror
                        *wo[0] = w.x, *wo[1] = w.y, *wo[2] = w.z, *wi[0] = wt.x, *wi[1] = wt.y, *wi[2] = wt.z;
                        break;
                    }
                    case 1: *wi[0] = *wo[0], *wi[1] = *wo[1], *wi[2] = -*wo[2]; break;  // h tilted away
                    case 2:  // wo grazing, wi steep on the other side
                        *wo[2] = std::copysign(0.02f, *wo[2]), *wi[2] = -std::copysign(0.9f, *wo[2]);
                        break;
                    default: *wo[2] = 1e-23f, *wi[2] = (i / 44) % 2 ? 3e-23f : -3e-23f; break;  // float z product 0
                }
            const double cs[] = {crit, -crit, crit / eta_ld, -crit / eta_ld};
            const float c = float(cs[(i / 5) % 4] * (1.0 + rel[i % 5]));
            switch (i % 13) {
                case 0: case 1: case 2: case 3: cos_i[k] = c; break;
                case 4: cos_i[k] = std::nextafter(float(cs[i % 4]), (i / 13) % 2 ? 2.f : -2.f); break;
                case 5: cos_i[k] = (i / 13) % 2 ? 0.f : -0.f; break;
                case 6: cos_i[k] = (i / 13) % 2 ? 1.f : -1.f; break;
                case 7: cos_i[k] = (i / 13) % 2 ? 1.0000001f : -1.0000001f; break;
                case 8: cos_i[k] = (i / 13) % 2 ? 1e-7f : -1e-7f; break;
                default: cos_i[k] = 2.f * rng.next_float() - 1.f; break;
            }
            kind[k] = mat[k] < 0 ? 0 : std::holds_alternative<RoughDielectric<GGX>>(mats[size_t(mat[k])]) ? 1 : 2;
            active[i] = (i / 16) % 3 != 1 || i % 5 != 0;  // every third packet partially masked
        }
        in.n = kN;
        for (int p = 0; p < kRoughDielectricParams; ++p) in.q[p] = q[p].data();
        for (int c = 0; c < 3; ++c) in.wo[c] = a[c].data(), in.wi[c] = a[3 + c].data(), in.u[c] = a[6 + c].data();
        in.cos_i = cos_i.data();
        in.kind = kind.data();
        in.active = active.get();
    }
    Vec3f wo(int i) const { return Vec3f(a[0][size_t(i)], a[1][size_t(i)], a[2][size_t(i)]); }
    Vec3f wi(int i) const { return Vec3f(a[3][size_t(i)], a[4][size_t(i)], a[5][size_t(i)]); }
};

using Outputs = test::ProbeOutputs<dielectric_probe::Out, dielectric_probe::kOutputs, Cases::kN>;
using test::same_bits;

void expect_equal(const Outputs& scalar, const Outputs& packet, const char* target) {
    EXPECT_EQ(test::count_differing(scalar, packet, target), 0u) << target;
}
}  // namespace

TEST(DielectricLanes, TheGridIsCovered) {
    const Cases cases;
    EXPECT_GE(cases.ggx, 20);
    EXPECT_GE(cases.beckmann, 20);
}

TEST(DielectricLanes, TheHalfVectorGridIsCovered) {
    // The half-vector step's cases, as the float function sees them: valid reflection and
    // transmission pairs from both sides, back-facing microfacets, pairs without a half vector,
    // near-critical transmission pairs on both sides of the critical angle; and Fresnel pairs in
    // and out of total internal reflection.
    const Cases cases;
    int refl[2] = {0, 0}, trans[2] = {0, 0}, back = 0, none = 0, critical_ok = 0, critical_not = 0, tir = 0, partial = 0;
    for (int i = 0; i < Cases::kN; ++i) {
        const float eta = cases.mat[size_t(i)] >= 0 ? cases.q[0][size_t(i)] : 1.5f;
        const Vec3f wo = cases.wo(i), wi = cases.wi(i);
        const DielectricHalf h = dielectric_half(wo, wi, eta);
        const bool reflect = wo.z * wi.z > 0.f;
        if (h.ok) (reflect ? refl : trans)[wo.z > 0.f ? 0 : 1] += 1;
        else if (h.dot_o != 0.f || h.dot_i != 0.f) ++back;
        else ++none;
        if (i % 11 == 10 && (i / 11) % 4 == 0) (h.ok && !reflect ? critical_ok : critical_not) += 1;
        float R, T;
        dielectric_fresnel_pair(cases.cos_i[size_t(i)], eta, &R, &T);
        (R == 1.f ? tir : partial) += 1;
    }
    for (int s = 0; s < 2; ++s) {
        EXPECT_GE(refl[s], 1000) << "side " << s;
        EXPECT_GE(trans[s], 1000) << "side " << s;
    }
    EXPECT_GE(back, 1000);
    EXPECT_GE(none, 500);
    EXPECT_GE(critical_ok, 50);
    EXPECT_GE(critical_not, 50);
    EXPECT_GE(tir, 1000);
    EXPECT_GE(partial, 5000);
}

namespace {
// The half-vector step and Fresnel written plainly, with glm's double vectors and branches (the
// form the lane template must reproduce): what dielectric_half must give, bit for bit.
// Fresnel with one reciprocal of η and one division for both polarisations:
// r_parl² + r_perp² = (a/b)² + (c/d)² = (a²d² + c²b²)/(b²d²).
double plain_fresnel(double cos_i, double eta) {
    cos_i = std::min(1.0, std::max(-1.0, cos_i));
    const double inv_eta = 1.0 / eta;
    double e = eta, inv_e = inv_eta;
    if (cos_i < 0.0) e = inv_eta, inv_e = eta, cos_i = -cos_i;
    if (eta == 1.0) return 0.0;
    const double sin2_t = std::max(0.0, 1.0 - cos_i * cos_i) * (inv_e * inv_e);
    if (sin2_t >= 1.0) return 1.0;
    const double cos_t = std::sqrt(1.0 - sin2_t);
    const double a = e * cos_i - cos_t, b = e * cos_i + cos_t, c = cos_i - e * cos_t, d = cos_i + e * cos_t;
    return std::min(1.0, 0.5 * ((a * a * (d * d) + c * c * (b * b)) / (b * b * (d * d))));
}
DielectricHalf plain_half(const Vec3f& wo, const Vec3f& wi, float eta) {
    DielectricHalf out;
    const float co = wo.z, ci = wi.z;
    if (co == 0.f || ci == 0.f) return out;
    const bool reflect = co * ci > 0.f;
    const double inv_eta = 1.0 / double(eta);
    const double etap = reflect ? 1.0 : (co > 0.f ? double(eta) : inv_eta);
    const double inv_etap = reflect ? 1.0 : (co > 0.f ? inv_eta : double(eta));
    const Vec3d h = Vec3d(wi) * etap + Vec3d(wo);
    const double hl = glm::length(h);
    if (!(hl > 0.0)) return out;
    const Vec3d wm = h * (1.0 / (h.z < 0.0 ? -hl : hl));
    const double dot_o = glm::dot(Vec3d(wo), wm), dot_i = glm::dot(Vec3d(wi), wm);
    out.wm = Vec3f(wm), out.dot_o = float(dot_o), out.dot_i = float(dot_i);
    if (out.dot_i * ci <= 0.f || out.dot_o * co <= 0.f) return out;
    const bool from_inside = !reflect && ((co > 0.f) != (eta >= 1.f));
    const double F = plain_fresnel(from_inside ? dot_i : dot_o, eta);
    out.R = float(F), out.T = float(1.0 - F);
    const float s = float(double(out.dot_i) + double(out.dot_o) * inv_etap);
    out.denom = reflect ? 0.f : s * s;
    out.etap2 = float(etap * etap);
    out.ok = true;
    return out;
}
}  // namespace

TEST(DielectricLanes, HalfStepIsThePlainDoubleComputation) {
    // The float function (the lane template's double instantiation) against the plain form, every
    // field bit for bit, over the grid (so the packets, equal to it, are equal to the plain form).
    const Cases cases;
    size_t differ = 0;
    for (int i = 0; i < Cases::kN; ++i) {
        const float eta = cases.mat[size_t(i)] >= 0 ? cases.q[0][size_t(i)] : 1.5f;
        const DielectricHalf a = dielectric_half(cases.wo(i), cases.wi(i), eta);
        const DielectricHalf b = plain_half(cases.wo(i), cases.wi(i), eta);
        const float fa[] = {a.wm.x, a.wm.y, a.wm.z, a.dot_o, a.dot_i, a.R, a.T, a.denom, a.etap2, float(a.ok)};
        const float fb[] = {b.wm.x, b.wm.y, b.wm.z, b.dot_o, b.dot_i, b.R, b.T, b.denom, b.etap2, float(b.ok)};
        for (int k = 0; k < 10; ++k)
            if (!same_bits(fa[k], fb[k]) && ++differ <= 5)
                ADD_FAILURE() << "field " << k << " case " << i << ": " << fa[k] << " vs plain " << fb[k];
        float R, T;
        dielectric_fresnel_pair(cases.cos_i[size_t(i)], eta, &R, &T);
        const double F = plain_fresnel(cases.cos_i[size_t(i)], eta);
        if ((!same_bits(R, float(F)) || !same_bits(T, float(1.0 - F))) && ++differ <= 5)
            ADD_FAILURE() << "Fresnel pair case " << i << ": " << R << " vs plain " << float(F);
    }
    EXPECT_EQ(differ, 0u);
}

TEST(DielectricLanes, FloatInstantiationIsTheScalarBxDF) {
    // The float instantiation from packet parameters gives the scalar API's bits: eval, pdf and
    // sample in each context, case by case; most cases sample something in each lobe.
    const Cases cases;
    Outputs scalar;
    dielectric_probe::run<float>(cases.in, scalar.out);
    size_t compared = 0, differ = 0, reflected = 0, transmitted = 0;
    auto check = [&](float x, float y, int k, int i) {
        ++compared;
        if (!same_bits(x, y) && ++differ <= 5)
            ADD_FAILURE() << "output " << k << " case " << i << ": packet form " << x << ", BxDF " << y;
    };
    for (int i = 0; i < Cases::kN; ++i) {
        if (cases.mat[size_t(i)] < 0 || !cases.active[i]) continue;
        const BxDF& b = cases.mats[size_t(cases.mat[size_t(i)])];
        const Vec3f wo = cases.wo(i), wi = cases.wi(i);
        const Vec2f u(cases.a[7][size_t(i)], cases.a[8][size_t(i)]);
        for (int c = 0; c < dielectric_probe::kContexts; ++c) {
            const BxDFContext ctx{dielectric_probe::kMode[c], dielectric_probe::kAllowed[c]};
            const int k0 = c * dielectric_probe::kPerContext;
            const Spectrum f = eval(b, ctx, wo, wi);
            for (int ch = 0; ch < 3; ++ch) check(scalar.at(k0 + ch, i), f[ch], k0 + ch, i);
            check(scalar.at(k0 + 3, i), pdf(b, ctx, wo, wi), k0 + 3, i);
            const auto s = sample(b, ctx, wo, cases.a[6][size_t(i)], u);
            check(scalar.at(k0 + 4, i), s ? 1.f : 0.f, k0 + 4, i);
            if (!s) continue;
            (has_flag(s->lobe, BxDFFlags::Transmission) ? transmitted : reflected) += 1;
            for (int ch = 0; ch < 3; ++ch) check(scalar.at(k0 + 5 + ch, i), s->wi[ch], k0 + 5 + ch, i);
            for (int ch = 0; ch < 3; ++ch) check(scalar.at(k0 + 8 + ch, i), s->weight[ch], k0 + 8 + ch, i);
            check(scalar.at(k0 + 11, i), s->pdf, k0 + 11, i);
            check(scalar.at(k0 + 12, i), s->eta, k0 + 12, i);
            check(scalar.at(k0 + 13, i), float(uint32_t(s->lobe)), k0 + 13, i);
        }
    }
    EXPECT_EQ(differ, 0u) << "of " << compared;
    EXPECT_GT(reflected, size_t(Cases::kN) / 2);
    EXPECT_GT(transmitted, size_t(Cases::kN));
}

TEST(DielectricLanes, EveryTargetEveryLane) {
    const Cases cases;
    Outputs scalar;
    dielectric_probe::run<float>(cases.in, scalar.out);
    int targets = 0;
    for (SimdTarget t : available_simd_targets()) {
        Outputs packet;
        switch (t) {
#ifdef PELLUCID_DIELECTRIC_PROBE_AVX512
            case SimdTarget::AVX512: dielectric_probe::run_avx512(cases.in, packet.out); break;
#endif
#ifdef PELLUCID_DIELECTRIC_PROBE_AVX2
            case SimdTarget::AVX2: dielectric_probe::run_avx2(cases.in, packet.out); break;
#endif
#ifdef PELLUCID_DIELECTRIC_PROBE_SSE4
            case SimdTarget::SSE4: dielectric_probe::run_sse4(cases.in, packet.out); break;
#endif
            default: continue;
        }
        ++targets;
        expect_equal(scalar, packet, to_string(t).c_str());
    }
    RecordProperty("targets", targets);
}

TEST(DielectricLanes, ACaseChangedInOneLaneIsSeen) {
    // The comparison itself: another α in one lane must change that lane's outputs only.
    Cases cases;
    Outputs a, b;
    dielectric_probe::run<float>(cases.in, a.out);
    int lane = 0;
    while (!(cases.kind[size_t(lane)] == 2 && cases.active[lane] && cases.wo(lane).z > 0.1f && cases.wi(lane).z > 0.1f))
        ++lane;
    const_cast<float*>(cases.in.q[9])[lane] *= 1.5f;
    dielectric_probe::run<float>(cases.in, b.out);
    const std::vector<int> changed = test::differing_cases(a, b);
    EXPECT_FALSE(changed.empty());
    for (int i : changed) EXPECT_EQ(i, lane);
}
