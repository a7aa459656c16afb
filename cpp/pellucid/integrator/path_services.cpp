// The one-lane parts of the path tracer (path_services.h).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/integrator/path_services.h"

#include <cstring>
#include <new>
#if PELLUCID_DISPATCH_STATS
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#if defined(__x86_64__)
#include <x86intrin.h>
#endif
#endif

#include "pellucid/sampling/mis.h"
#include "pellucid/scene/hit_packets.h"
#include "pellucid/scene/scene.h"

namespace pellucid {

#if PELLUCID_DISPATCH_STATS
namespace {
// Index 2 + kind: 0 the packet passes (kind −2), 1 the kernel's tiles (−1), then the packet forms.
// Every counter is a sum, so the totals do not depend on the thread count.
struct DispatchCounts {
    std::atomic<uint64_t> calls{0}, lanes{0}, cycles{0};
    std::atomic<int> width{0};
};
DispatchCounts g_dispatch[2 + 32];
void print_dispatch() {
    for (int i = 0; i < 2 + 32; ++i) {
        const DispatchCounts& d = g_dispatch[i];
        if (!d.calls) continue;
        std::fprintf(stderr, "dispatch form %d calls %llu lanes %llu width %d cycles %llu\n", i - 2,
                     static_cast<unsigned long long>(d.calls.load()), static_cast<unsigned long long>(d.lanes.load()),
                     d.width.load(), static_cast<unsigned long long>(d.cycles.load()));
    }
}
}  // namespace

uint64_t dispatch_clock() {
#if defined(__x86_64__)
    return __rdtsc();
#else
    return uint64_t(std::chrono::steady_clock::now().time_since_epoch().count());
#endif
}

void dispatch_record(int kind, int lanes, int width, uint64_t cycles) {
    static const bool registered = (std::atexit(print_dispatch), true);
    (void)registered;
    DispatchCounts& d = g_dispatch[2 + kind];
    d.calls.fetch_add(1, std::memory_order_relaxed);
    d.lanes.fetch_add(uint64_t(lanes), std::memory_order_relaxed);
    d.cycles.fetch_add(cycles, std::memory_order_relaxed);
    d.width.store(width, std::memory_order_relaxed);
}
#endif

namespace {
/// A conductor's packet form and parameters (PathSetup::packet_params), if it has one.
bool packet_conductor(const BxDF& b, int32_t* kind, float* q) {
    SmoothConductorT<float> smooth;
    auto put = [&](const SmoothConductorT<float>& c) {
        for (int ch = 0; ch < 3; ++ch) q[ch] = c.eta[ch], q[3 + ch] = c.k[ch], q[6 + ch] = c.scale[ch];
    };
    if (const auto* c = std::get_if<SmoothConductor<ConductorFresnel>>(&b); c && c->lanes(&smooth)) {
        *kind = kPacketSmoothConductor;
        put(smooth);
        return true;
    }
    // The rough conductors, GGX or Beckmann (rough_kind), or the mirror they collapse to.
    auto rough_or_mirror = [&](const auto& c, int32_t rough_kind) {
        typename std::decay_t<decltype(c)>::Lanes rough;
        if (c.lanes(&rough)) {
            *kind = rough_kind;
            put(rough.fr);
            q[9] = rough.d.ax, q[10] = rough.d.ay, q[11] = rough.d.separable ? 1.f : 0.f;
            return true;
        }
        if (c.distribution().effectively_smooth() && c.smooth().lanes(&smooth)) {
            *kind = kPacketSmoothConductor;
            put(smooth);
            return true;
        }
        return false;
    };
    if (const auto* c = std::get_if<RoughConductor>(&b)) return rough_or_mirror(*c, kPacketRoughConductor);
    if (const auto* c = std::get_if<RoughConductorBeckmann>(&b)) return rough_or_mirror(*c, kPacketRoughConductorBeckmann);
    return false;
}

static_assert(kRoughDielectricParams <= kPacketParams, "a rough dielectric's parameters fit a material's");
static_assert(kOrenNayarParams <= kPacketParams, "Oren–Nayar's parameters fit a material's");
static_assert(kPlasticParams <= kPacketParams, "a plastic's parameters fit a material's packet parameters");

/// A plastic's packet form and parameters (plastic_packet_params): smooth, or rough over GGX or
/// Beckmann.
bool packet_plastic(const BxDF& b, int32_t* kind, float* q, std::vector<float>* tables, const float* coat_offset = nullptr) {
    int32_t k = kPacketPlastic;
    if (const auto* p = std::get_if<SmoothPlastic>(&b)) {
        plastic_packet_params(p->base(), nullptr, tables, q, coat_offset);
    } else if (const auto* r = std::get_if<RoughPlastic<GGX>>(&b)) {
        const GGXT<float> d = r->distribution().lanes();
        plastic_packet_params(r->base(), &d, tables, q, coat_offset);
    } else if (const auto* rb = std::get_if<RoughPlastic<Beckmann>>(&b)) {
        const BeckmannT<float> d = rb->distribution().lanes();
        const GGXT<float> alphas{d.ax, d.ay, d.separable};  // (only α and the shadowing are stored)
        plastic_packet_params(rb->base(), &alphas, tables, q, coat_offset);
        k = kPacketPlasticBeckmann;
    } else {
        return false;  // (kind untouched: the material stays a BSDF lane)
    }
    *kind = k;
    return true;
}
/// A rough dielectric's packet form: rough and without multiple scattering (has_lanes); its
/// parameters by rough_dielectric_packet_params.
bool packet_rough_dielectric(const BxDF& b, int32_t* kind, float* q) {
    auto put = [&](const auto& r, int32_t k) {
        if (!r.has_lanes()) return false;
        rough_dielectric_packet_params(r.lanes(), q);
        *kind = k;
        return true;
    };
    if (const auto* r = std::get_if<RoughDielectric<GGX>>(&b)) return put(*r, kPacketRoughDielectric);
    if (const auto* r = std::get_if<RoughDielectric<Beckmann>>(&b)) return put(*r, kPacketRoughDielectricBeckmann);
    return false;
}

static_assert(kPrincipledParams <= kPacketParams, "a principled BSDF's parameters fit a material's");
static_assert(kPrincipledThinParams <= kPacketParams, "a thin principled BSDF's parameters fit a material's");
static_assert(kPrincipledSolidParams <= kPacketParams, "a principled solid's parameters fit a material's");
/// A principled BSDF's packet form: the opaque solid (has_lanes; its parameters by
/// principled_packet_params), the thin sheet (principled_thin_packet_params) or the solid with a
/// transmission lobe (principled_solid_packet_params).
bool packet_principled(const BxDF& b, int32_t* kind, float* q) {
    const auto* p = std::get_if<PrincipledBSDF>(&b);
    if (!p) return false;
    if (p->thin()) {
        principled_thin_packet_params(p->thin_lanes(), q);
        *kind = kPacketPrincipledThin;
        return true;
    }
    if (!p->has_lanes()) {
        principled_solid_packet_params(p->solid_lanes(), q);
        *kind = kPacketPrincipledSolid;
        return true;
    }
    principled_packet_params(p->lanes(), q);
    *kind = kPacketPrincipled;
    return true;
}
static_assert(kPrincipled2012Params <= kPacketParams, "a 2012 principled BRDF's parameters fit a material's");
/// The Burley 2012 principled BRDF's packet form (always); its parameters by principled2012_packet_params.
bool packet_principled2012(const BxDF& b, int32_t* kind, float* q) {
    const auto* p = std::get_if<Principled>(&b);
    if (!p) return false;
    principled2012_packet_params(p->lanes(), q);
    *kind = kPacketPrincipled2012;
    return true;
}
}  // namespace

int packet_param_count(int32_t kind) {
    switch (kind) {
        case kPacketLambertian: return 3;
        case kPacketSmoothDielectric:
        case kPacketThinDielectric: return 7;
        case kPacketSmoothConductor: return 9;
        case kPacketRoughConductor:
        case kPacketRoughConductorBeckmann: return 12;
        case kPacketPlastic:
        case kPacketPlasticBeckmann: return kPlasticParams;
        case kPacketRoughDielectric:
        case kPacketRoughDielectricBeckmann: return kRoughDielectricParams;
        case kPacketPrincipled: return kPrincipledParams;
        case kPacketPrincipled2012: return kPrincipled2012Params;
        case kPacketPrincipledThin: return kPrincipledThinParams;
        case kPacketPrincipledSolid: return kPrincipledSolidParams;
        case kPacketOrenNayar: return kOrenNayarParams;
        default: return 0;
    }
}

namespace {
/// The packet form of b and its parameters into q (kPacketParams floats), or kBSDFLane. The rough
/// plastics' coat tables are appended to `tables`; without tables the plastics have none.
int32_t packet_form_of(const BxDF& b, float* q, std::vector<float>* tables) {
    int32_t kind = kBSDFLane;
    if (const Lambertian* l = std::get_if<Lambertian>(&b)) {
        for (int c = 0; c < 3; ++c) q[c] = l->albedo()[c];
        return kPacketLambertian;
    }
    if (const SmoothDielectric* d = std::get_if<SmoothDielectric>(&b)) {
        const SmoothDielectricT<float> p = d->lanes();
        q[0] = p.eta;
        for (int c = 0; c < 3; ++c) q[1 + c] = p.r[c], q[4 + c] = p.t[c];
        return kPacketSmoothDielectric;
    }
    if (const ThinDielectric* t = std::get_if<ThinDielectric>(&b)) {
        const ThinDielectricT<float> p = t->lanes();
        q[0] = p.eta;
        for (int c = 0; c < 3; ++c) q[1 + c] = p.r[c], q[4 + c] = p.t[c];
        return kPacketThinDielectric;
    }
    if (const OrenNayar* o = std::get_if<OrenNayar>(&b)) {
        oren_nayar_packet_params(o->lanes(), q);
        return kPacketOrenNayar;
    }
    if (packet_conductor(b, &kind, q) || (tables && packet_plastic(b, &kind, q, tables)) ||
        packet_rough_dielectric(b, &kind, q) || packet_principled(b, &kind, q) ||
        packet_principled2012(b, &kind, q))
        return kind;
    return kBSDFLane;
}

/// The rough coat's table of a plastic, or null (another model, or a smooth coat).
const RoughCoatTable* plastic_coat_table(const BxDF& b) {
    if (const auto* r = std::get_if<RoughPlastic<GGX>>(&b)) return r->base().coat_table();
    if (const auto* r = std::get_if<RoughPlastic<Beckmann>>(&b)) return r->base().coat_table();
    if (const auto* p = std::get_if<SmoothPlastic>(&b)) return p->base().coat_table();
    return nullptr;
}
}  // namespace

namespace path_services {
int32_t packet_form(const PathSetup& ps, uint32_t m, const BSDF& b, float* q) {
    const int32_t kind = packet_form_of(b.bxdf(), q, nullptr);
    if (kind != kBSDFLane) return kind;
    // A plastic: its packet form where its coat is smooth or its rough coat's table is the
    // material's, whose offset in the tables the setup found.
    const RoughCoatTable* t = plastic_coat_table(b.bxdf());
    if (t && t != ps.textured_coat[m]) return kBSDFLane;
    int32_t k = kBSDFLane;  // (no tables: a smooth coat has none, a rough one has its offset)
    return packet_plastic(b.bxdf(), &k, q, nullptr, &ps.textured_coat_offset[m]) ? k : kBSDFLane;
}
}  // namespace path_services

namespace {
// A material a vertex lane shades (the kernel's record_hit: a packet form, and no delta lobe
// where the scene carries ray differentials; or one of PathSetup::tex_lanes), as the tables hold
// it: its index, else −1.
int32_t lane_material(const Scene& scene, const PathSetup& ps, uint32_t m) {
    const bool form = ps.packet_kind[m] != kBSDFLane || ps.tex_lane[m] >= 0;
    const bool lane = form && !(scene.needs_footprints && is_specular(BxDFFlags(ps.packet_flags[m])));
    return lane ? int32_t(m) : -1;
}

// PathSetup::sphere_row and sphere_table.
void make_sphere_table(const Scene& scene, PathSetup* ps) {
    if (ps->media || ps->subsurface) return;
    ps->sphere_row.assign(scene.shapes.size(), -1);
    int32_t rows = 0;
    for (size_t g = 0; g < scene.shapes.size(); ++g) {
        const ShapeRecord& s = scene.shapes[g];
        if (s.kind != ShapeRecord::Kind::Sphere || s.light >= 0 || s.null_surface) continue;
        ps->sphere_row[g] = rows++;
        float r[PathSetup::kSphereStride] = {s.center.x, s.center.y, s.center.z, s.radius};
        for (int c = 0; c < 9; ++c) r[4 + c] = s.rotation[c / 3][c % 3];
        r[13] = s.flip_normals ? 1.f : 0.f;
        const int32_t id = lane_material(scene, *ps, s.material);
        std::memcpy(&r[14], &id, sizeof id);
        ps->sphere_table.insert(ps->sphere_table.end(), r, r + PathSetup::kSphereStride);
    }
    if (rows == 0) ps->sphere_row.clear();
}

// PathSetup::tri_base and tri_table.
void make_triangle_table(const Scene& scene, PathSetup* ps) {
    if (ps->media || ps->subsurface) return;
    ps->tri_base.assign(scene.shapes.size(), -1);
    size_t total = 0;
    auto eligible = [&](const ShapeRecord& s) {
        if (s.kind != ShapeRecord::Kind::Mesh || s.light >= 0 || s.null_surface) return false;
        const TriangleMesh& m = scene.meshes[s.mesh_index];
        return !m.flat.empty() && m.triangle_count() > 0;
    };
    for (const ShapeRecord& s : scene.shapes)
        if (eligible(s)) total += scene.meshes[s.mesh_index].triangle_count();
    if (total == 0 || total > PathSetup::kMaxTriangleTable) {
        ps->tri_base.clear();
        return;
    }
    ps->tri_table.assign(total * PathSetup::kTriStride, 0.f);
    const bool uvs = !ps->tex_lanes.empty();
    if (uvs) ps->tri_uv.assign(total * PathSetup::kTriUVStride, 0.f);
    size_t next = 0;
    for (size_t g = 0; g < scene.shapes.size(); ++g) {
        const ShapeRecord& s = scene.shapes[g];
        if (!eligible(s)) continue;
        const TriangleMesh& mesh = scene.meshes[s.mesh_index];
        ps->tri_base[g] = int32_t(next);
        for (size_t t = 0; t < mesh.triangle_count(); ++t, ++next) {
            float* r = &ps->tri_table[next * PathSetup::kTriStride];
            for (int k = 0; k < 3; ++k) {
                const Point3f& p = mesh.positions[mesh.indices[3 * t + size_t(k)]];
                r[3 * k] = p.x, r[3 * k + 1] = p.y, r[3 * k + 2] = p.z;
            }
            const FlatTriangle& f = mesh.flat[t];
            const Vec3f v[4] = {f.ng, f.shading.s, f.shading.t, f.shading.n};
            for (int k = 0; k < 4; ++k) r[9 + 3 * k] = v[k].x, r[10 + 3 * k] = v[k].y, r[11 + 3 * k] = v[k].z;
            const uint32_t m = s.face_materials.empty() ? s.material : s.face_materials[t];
            const int32_t id = lane_material(scene, *ps, m);
            std::memcpy(&r[21], &id, sizeof id);
            if (uvs) {
                float* uv = &ps->tri_uv[next * PathSetup::kTriUVStride];
                const Vec2f none[3] = {Vec2f(0.f, 0.f), Vec2f(1.f, 0.f), Vec2f(1.f, 1.f)};
                for (int k = 0; k < 3; ++k) {
                    const Vec2f c = mesh.uvs.empty() ? none[k] : mesh.uvs[mesh.indices[3 * t + size_t(k)]];
                    uv[2 * k] = c.x, uv[2 * k + 1] = c.y;
                }
                const Vec3f dp[2] = {f.dpdu, f.dpdv};
                for (int k = 0; k < 2; ++k) uv[8 + 3 * k] = dp[k].x, uv[9 + 3 * k] = dp[k].y, uv[10 + 3 * k] = dp[k].z;
            }
        }
    }
}

// An image texture as the packet pass looks it up (PathSetup::tex_lane): kept in memory, with the
// Repeat wrap and indices within an int32; a grey one of three channels from a one-channel copy
// (PathSetup::grey_images, shared by the materials that read it). True: *out is it.
bool lane_image(const ImageTexture& t, LaneImage* out, PathSetup* ps) {
    const ImageTextureHandle& h = t.handle;
    const int n = h.channels >= 3 ? 3 : 1;
    const size_t texels = size_t(h.width) * size_t(h.height);
    if (!h.texels || t.wrap != TextureWrap::Repeat || h.width <= 0 || h.height <= 0 || texels * size_t(n) >= (size_t(1) << 31))
        return false;
    *out = LaneImage{h.texels, h.width, h.height, n};
    if (n != 3) return true;
    for (size_t i = 0; i < texels; ++i) {
        const float* p = h.texels + 3 * i;
        if (std::memcmp(p, p + 1, sizeof(float)) != 0 || std::memcmp(p, p + 2, sizeof(float)) != 0) return true;
    }
    for (const PathSetup::GreyImage& g : ps->grey_images)
        if (g.source == h.texels) {
            *out = LaneImage{g.texels->data(), h.width, h.height, 1};
            return true;
        }
    auto grey = std::make_shared<std::vector<float>>(texels);
    for (size_t i = 0; i < texels; ++i) (*grey)[i] = h.texels[3 * i];
    *out = LaneImage{grey->data(), h.width, h.height, 1};
    ps->grey_images.push_back({h.texels, std::move(grey)});
    return true;
}
void put_uv(const UVTransform& a, float* uv) {
    const float v[6] = {a.a00, a.a01, a.b0, a.a10, a.a11, a.b1};
    std::copy(v, v + 6, uv);
}

// The diffuse base of a rough plastic BxDF, or null.
const PlasticBase* rough_plastic_base(const BxDF& b) {
    if (const auto* r = std::get_if<RoughPlastic<GGX>>(&b)) return &r->base();
    if (const auto* r = std::get_if<RoughPlastic<Beckmann>>(&b)) return &r->base();
    return nullptr;
}

// PathSetup::tex_lane: material m (two-sided, built at each hit, whose BxDF has the packet form
// `kind` with the parameters q, a rough plastic's coat table among the tables) as the packet pass
// evaluates it, if it can. True: it joins tex_lanes.
bool tex_lane_material(const Scene& scene, size_t m, int32_t kind, const float* q, PathSetup* ps) {
    const MaterialTextures& mt = scene.material_textures[m];
    if (scene.needs_footprints || mt.normal_map >= 0) return false;
    PathSetup::TexLaneMaterial t;
    t.kind = kind;
    const Tex<Spectrum>* refl = nullptr;  // the Lambertian's reflectance or the plastic's Kd
    if (const auto* lp = std::get_if<LambertianParams>(&scene.materials[m]); lp && kind == kPacketLambertian) {
        refl = &lp->reflectance;
    } else if (const auto* rp = std::get_if<RoughPlasticParams>(&scene.materials[m]);
               rp && (kind == kPacketPlastic || kind == kPacketPlasticBeckmann)) {
        // Glossy at every hit (α and η are constant): its lanes go on, with NEE, whatever Kd is.
        const BxDF& b = scene.material_bxdfs[m];
        const PlasticBase* base = rough_plastic_base(b);
        if (!base || !has_flag(flags(b), BxDFFlags::GlossyReflection) || rp->plastic.specular_reflectance.textured() ||
            rp->plastic.int_ior.textured() || rp->plastic.ext_ior.textured())
            return false;
        refl = &rp->plastic.diffuse_reflectance;
        std::copy(q, q + kPacketParams, t.q);
        t.eta = base->eta(), t.rbar = base->internal_reflectance(), t.variant = base->variant();
    } else {
        return false;
    }
    if (mt.count != (refl->textured() ? 1 : 0)) return false;
    if (!refl->textured()) {
        std::copy(q, q + 3, t.albedo[0]);  // (a Lambertian: its packet parameters are its albedo)
        if (kind != kPacketLambertian) for (int c = 0; c < 3; ++c) t.albedo[0][c] = refl->value[c];
    } else {
        const Texture& tex = scene.textures[size_t(refl->texture)];
        t.lo = refl->lo, t.hi = refl->hi;
        if (const auto* im = std::get_if<ImageTexture>(&tex)) {
            if (im->filter != TextureFilter::Bilinear || !lane_image(*im, &t.image, ps)) return false;
            t.reflectance = PathSetup::TexLaneMaterial::kImage;
            put_uv(im->to_uv, t.to_uv);
        } else if (const auto* cb = std::get_if<CheckerboardTexture>(&tex); cb && !cb->filtered) {
            t.reflectance = PathSetup::TexLaneMaterial::kChecker;
            for (int c = 0; c < 3; ++c)  // (make_bxdf's Lambertian of each colour, clamped as TexEval)
                t.albedo[0][c] = clamp(cb->color0[c], t.lo, t.hi), t.albedo[1][c] = clamp(cb->color1[c], t.lo, t.hi);
            put_uv(cb->to_uv, t.to_uv);
        } else {
            return false;
        }
    }
    if (mt.bump >= 0) {
        if (mt.bump_model != BumpModel::Mitsuba || mt.invalid_normals == InvalidNormals::Bend) return false;
        const Texture& tex = scene.textures[size_t(mt.bump)];
        if (const auto* im = std::get_if<ImageTexture>(&tex)) {
            if (!lane_image(*im, &t.height, ps)) return false;  // (the gradient reads the full image, whatever its filter)
            t.bump_image = true;
            put_uv(im->to_uv, t.height_uv);
        } else if (!std::holds_alternative<ConstantTexture>(tex)) {
            return false;
        }
        t.bump = true;
        t.bump_scale = mt.bump_scale;
        t.mirror = mt.invalid_normals == InvalidNormals::Mirror;
        t.soften = mt.terminator_softening;
        t.estevez = mt.terminator_model == TerminatorModel::Estevez;
    }
    ps->tex_tangents = ps->tex_tangents || t.bump;
    ps->tex_lane[m] = int32_t(ps->tex_lanes.size());
    ps->tex_lanes.push_back(t);
    return true;
}
}  // namespace

PathSetup make_path_setup(const Scene& scene, int max_depth, int rr_depth, bool use_nee, bool use_mis, SamplerType type) {
    PathSetup ps;
    ps.scene = &scene;
    // "Unbounded" stops at kUnboundedDepth: Russian roulette does not end a path whose throughput
    // stays 1 at medium collisions (a lossless medium walled in by mirrors would never end).
    ps.max_depth = max_depth < 0 ? kUnboundedDepth : max_depth;
    ps.rr_depth = rr_depth;
    ps.use_nee = use_nee && !scene.lights.empty() && scene.nee_lights;
    ps.use_mis = use_mis;
    ps.sampler = type;
    const size_t n = scene.material_bxdfs.size();
    ps.packet_kind.assign(n, kBSDFLane);
    ps.packet_params.assign(kPacketParams * n + PathSetup::kPacketParamsPad, 0.f);
    ps.packet_flags.assign(n, 0u);
    ps.textured_packet.assign(n, 0);
    ps.textured_coat.assign(n, nullptr);
    ps.textured_coat_offset.assign(n, 0.f);
    ps.tex_lane.assign(n, -1);
    for (size_t m = 0; m < n; ++m) {
        const MaterialTextures& mt = scene.material_textures[m];
        if (!mt.two_sided) continue;
        // A subsurface boundary's transmission goes through the probe (subsurface_entry).
        if (std::holds_alternative<SubsurfaceParams>(scene.materials[m])) continue;
        const BxDF& b = scene.material_bxdfs[m];
        if (mt.has_textured_params() || mt.perturbs_normal()) {
            // Built at each hit (textures, a bump or normal map): the packet form of the model shades
            // it where its BSDF there has one (packet_form). A plastic's rough coat table is the
            // same at every hit (α and η are not textured): it joins the tables here.
            float q[kPacketParams] = {};
            int32_t kind = packet_form_of(b, q, nullptr);
            if (kind == kBSDFLane && packet_plastic(b, &kind, q, &ps.coat_tables)) {
                ps.textured_coat[m] = plastic_coat_table(b);
                ps.textured_coat_offset[m] = ps.textured_coat[m] ? q[kPlasticCoatParam] : 0.f;
            }
            ps.textured_packet[m] = kind != kBSDFLane;
            if (kind != kBSDFLane) tex_lane_material(scene, m, kind, q, &ps);
            continue;
        }
        ps.packet_kind[m] = packet_form_of(b, &ps.packet_params[kPacketParams * m], &ps.coat_tables);
        if (ps.packet_kind[m] != kBSDFLane) ps.packet_flags[m] = uint32_t(flags(b));
    }
    ps.packet_count.resize(n);
    for (size_t m = 0; m < n; ++m) {
        ps.packet_count[m] = packet_param_count(ps.packet_kind[m]);
        ps.max_packet_count = std::max(ps.max_packet_count, ps.packet_count[m]);
    }
    std::vector<float> pmf(scene.lights.size());
    for (size_t i = 0; i < pmf.size(); ++i) pmf[i] = scene.light_pmf(i);
    ps.emitters = make_emitter_table(scene.lights, pmf);
    if (ps.emitters.empty()) ps.lights = make_light_table(scene.lights, pmf);
    ps.media = scene.has_media();
    ps.homogeneous_media.assign(scene.media.size(), 0);
    ps.medium_rows.assign(scene.media.size() * PathSetup::kMediumStride, 0.f);
    for (size_t k = 0; k < scene.media.size(); ++k) {
        const auto* h = std::get_if<HomogeneousMedium>(&scene.media[k]);
        if (!h) continue;
        ps.homogeneous_media[k] = 1;
        ps.any_homogeneous = true;
        const Spectrum st = h->sigma_t();
        float* row = &ps.medium_rows[k * PathSetup::kMediumStride];
        for (int c = 0; c < 3; ++c) row[c] = st[c], row[3 + c] = h->sigma_s[c], row[6 + c] = h->le[c];
    }
    ps.camera_medium = scene.camera_medium;
    ps.medium_nee = scene.integrator.medium_nee;
    ps.uniform_channels = scene.integrator.channel_sampling == "uniform";
    ps.subsurface = !scene.subsurface.empty();
    make_triangle_table(scene, &ps);
    make_sphere_table(scene, &ps);
    for (size_t g = 0; g < scene.shapes.size(); ++g) {  // (the table's lanes read their rows instead)
        const bool in_table = g < ps.tri_base.size() && ps.tri_base[g] >= 0;
        ps.prefetch_hits |= !in_table && large_mesh(scene, uint32_t(g)) != nullptr;
    }
    return ps;
}

namespace path_services {

void start_sample(const PathSetup& ps, bool splat, int x, int y, int sample, const Sampler::PixelSeed& px, Sampler* sampler,
                  float* fx, float* fy) {
    *sampler = Sampler(ps.sampler, px, uint64_t(sample));
    film_position(*ps.scene, splat, x, y, *sampler, fx, fy);
}

Sampler::PixelSeed pixel_seed(const PathSetup& ps, int x, int y, uint64_t seed) {
    return Sampler::PixelSeed::of(ps.sampler, uint64_t(y) * uint64_t(ps.scene->width) + uint64_t(x), seed);
}

void trace_lanes(const Scene& scene, int n, const float* const soa[7], const bool* valid, HitLanes& h, bool* hit) {
    if (n == 1) {
        RayHit r;
        if (valid[0]) {
            r.t = soa[6][0];
            scene.accel.intersect(Ray{Vec3f(soa[0][0], soa[1][0], soa[2][0]), Vec3f(soa[3][0], soa[4][0], soa[5][0]), soa[6][0]}, r);
        }
        h.t[0] = r.t, h.geom_id[0] = r.geom_id, h.prim_id[0] = r.prim_id, h.u[0] = r.u, h.v[0] = r.v;
    } else {
        scene.accel.intersect_lanes(n, soa, valid, h);
    }
    for (int i = 0; i < n; ++i) hit[i] = valid[i] & h.hit(i);  // (bitwise: no branch a lane)
}

void occluded_lanes(const Scene& scene, int n, const float* const soa[7], const bool* valid, bool* blocked) {
    if (n == 1) {
        blocked[0] = valid[0] && scene.occluded(Ray{Vec3f(soa[0][0], soa[1][0], soa[2][0]),
                                                    Vec3f(soa[3][0], soa[4][0], soa[5][0]), soa[6][0]});
        return;
    }
    scene.accel.occluded_lanes(n, soa, valid, blocked);
}

Spectrum escaped(const PathSetup& ps, const LightSampleContext& prev, const Vec3f& d, bool specular, float prev_pdf) {
    const Scene& scene = *ps.scene;
    Spectrum L(0.f);
    for (uint32_t li : scene.infinite_lights) {
        const InfiniteHit env = infinite_hit(scene.lights[li], prev, d);
        const float lpdf = scene.light_pmf(li) * env.pdf;
        L += env.Le * bsdf_hit_weight<float>(ps.use_mis, ps.use_nee, specular, prev_pdf, lpdf);
    }
    return L;
}

Spectrum emitted(const PathSetup& ps, const SurfaceInteraction& si, const LightSampleContext& prev, const Vec3f& d,
                 bool specular, float* light_pdf) {
    const Scene& scene = *ps.scene;
    *light_pdf = 0.f;
    const Spectrum Le = scene.emitted(si);
    if (Le.is_black() || specular) return Le;
    const auto& al = std::get<AreaLight>(scene.lights[size_t(si.light_id)]);
    *light_pdf = scene.light_pmf(size_t(si.light_id)) * al.pdf_li(prev, d, si.p, si.ng);
    return Le;
}

void footprint(const PathSetup& ps, SurfaceInteraction& si, const RayDifferential& ray) {
    ps.scene->compute_footprint(si, ray);
}

BxDFFlags bsdf_begin(const PathSetup& ps, SurfaceInteraction& si, const RayDifferential& ray, BSDF* out) {
    const Scene& scene = *ps.scene;
    // The pixel footprint, for texture filtering and bump steps (and to carry differentials on).
    if (scene.needs_footprints) scene.compute_footprint(si, ray);
    new (out) BSDF(scene.bsdf(si));
    return out->flags();
}

Spectrum bsdf_eval(const BSDF& bsdf, const Vec3f& wo, const Vec3f& wi, float* pdf) {
    return bsdf.eval(wo, wi, TransportMode::Radiance, pdf);
}

bool bsdf_sample(const BSDF& bsdf, const Vec3f& wo, float u_lobe, Vec2f u, BxDFSample* out) {
    auto s = bsdf.sample(wo, u_lobe, u);
    if (!s) return false;
    *out = *s;
    return true;
}

namespace {
constexpr int kVertexDims = 7;  ///< dimensions per path vertex (the layout at the top of path.cpp)
}  // namespace

void randoms(Sampler& sampler, int depth, bool nee, bool roulette, VertexRandoms* out) {
    const int dim0 = Sampler::kPixelDims + kVertexDims * (depth - 1);
    if (nee) {
        sampler.set_dimension(dim0);
        out->u[0] = sampler.get_1d();
        const Vec2f u = sampler.get_2d();
        out->u[1] = u.x;
        out->u[2] = u.y;
    }
    sampler.set_dimension(dim0 + 3);
    out->u[3] = sampler.get_1d();
    const Vec2f u = sampler.get_2d();
    out->u[4] = u.x;
    out->u[5] = u.y;
    if (roulette) {
        sampler.set_dimension(dim0 + 6);
        out->u[6] = sampler.get_1d();
    }
}

bool sample_light(const PathSetup& ps, const SurfaceInteraction& si, float u_sel, Vec2f u, LightLiSample* out,
                  float* light_pdf, Ray* shadow) {
    float pmf;
    const int32_t li = pick_light(ps, u_sel, &pmf);
    return sample_picked_light(ps, si, li, pmf, u, out, light_pdf, shadow);
}

int32_t pick_light(const PathSetup& ps, float u_sel, float* pmf) {
    if (ps.emitters.empty()) return pick_light_lanes<float>(ps.lights, u_sel, pmf);
    return int32_t(ps.scene->sample_light(u_sel, pmf));
}

bool sample_picked_light(const PathSetup& ps, const SurfaceInteraction& si, int32_t li, float pmf, Vec2f u,
                         LightLiSample* out, float* light_pdf, Ray* shadow) {
    const LightSampleContext ctx{si.p, si.ng};
    auto ls = std::visit([&](const auto& l) { return l.sample_li(ctx, u); }, ps.scene->lights[size_t(li)]);
    if (!ls || !(ls->pdf > 0.f)) return false;
    *out = *ls;
    *light_pdf = pmf * ls->pdf;
    *shadow = ls->infinite ? si.spawn_ray(ls->wi) : si.spawn_ray_to(ls->p_light, ls->n_light, ls->p_error);
    return true;
}

RayDifferential next_ray(const PathSetup& ps, const SurfaceInteraction& si, const RayDifferential& in, const Vec3f& wi,
                         bool specular, bool transmission, float eta) {
    const Scene& scene = *ps.scene;
    if (scene.needs_footprints && specular && in.has_differentials)
        return scene.specular_differentials(si, in, si.spawn_ray(wi), transmission, eta);
    return RayDifferential(si.spawn_ray(wi));
}

PCG32 medium_rng(const PathSetup& ps, int x, int y, int sample, uint64_t seed) {
    // The sampler's streams use the seed as given; this one mixes in a constant so the two differ.
    return PCG32::for_sample(uint64_t(y) * uint64_t(ps.scene->width) + uint64_t(x), uint64_t(sample),
                             seed ^ 0x6d656469756d7321ULL);
}

bool is_null_surface(const PathSetup& ps, const SurfaceInteraction& si) {
    return ps.scene->shapes[si.shape_id].null_surface;
}

int32_t medium_after(const PathSetup& ps, const SurfaceInteraction& si, const Vec3f& w, int32_t current) {
    const ShapeRecord& sh = ps.scene->shapes[si.shape_id];
    if (sh.interior_medium < 0 && sh.exterior_medium < 0) return current;  // not a medium boundary
    return dot(w, si.ng) < 0.f ? sh.interior_medium : sh.exterior_medium;
}

MediumEvent medium_sample(const PathSetup& ps, int32_t m, const Ray& ray, const Spectrum& beta, PCG32& rng) {
    auto u = [&] { return rng.next_float(); };
    return sample_distance(ps.scene->media[size_t(m)], ray, ps.uniform_channels ? Spectrum(1.f) : beta, u);
}

void medium_vertex(const Ray& ray, float t, SurfaceInteraction* out) {
    *out = SurfaceInteraction{};
    out->p = ray.o + ray.d * t;
    out->wo = -normalize(ray.d);
    out->ng = Normal3f(0.f);
    out->shading = Frame::from_z(out->wo);
    out->light_id = -1;
}

RayDifferential cross_boundary(const SurfaceInteraction& si, const Vec3f& d) { return RayDifferential(si.spawn_ray(d)); }

Spectrum phase_eval(const PathSetup& ps, int32_t m, const Vec3f& wo, const Vec3f& wi, float* pdf_out) {
    const PhaseFunction& ph = phase_of(ps.scene->media[size_t(m)]);
    const float p = eval(ph, wo, wi);
    *pdf_out = pdf(ph, wo, wi);
    return Spectrum(p);
}

bool phase_sample(const PathSetup& ps, int32_t m, const Vec3f& wo, Vec2f u, BxDFSample* out) {
    const auto s = sample(phase_of(ps.scene->media[size_t(m)]), wo, u);
    if (!s || !(s->pdf > 0.f)) return false;
    out->wi = s->wi;
    out->weight = Spectrum(s->weight);
    out->pdf = s->pdf;
    out->eta = 1.f;
    out->lobe = s->delta ? BxDFFlags::SpecularReflection : BxDFFlags::DiffuseReflection;
    return true;
}

Spectrum shadow_transmittance(const PathSetup& ps, int32_t m, const Ray& shadow, const Spectrum& beta, PCG32& rng,
                              const RayHit* first) {
    const Scene& scene = *ps.scene;
    auto u = [&] { return rng.next_float(); };
    Spectrum tr(1.f);
    Ray r = shadow;
    // The segment's far end, which every continuation after a null boundary aims at.
    const bool finite = std::isfinite(shadow.tmax);
    const Point3f end = finite ? shadow.o + shadow.d * shadow.tmax : Point3f(0.f);
    for (int crossings = 0; crossings < 256; ++crossings) {
        // The hit's record only where the ray goes on through a null boundary: any other surface
        // blocks it, and its record would be of no use (nor does a texture read it: no uv).
        RayHit h;
        h.t = r.tmax;
        const bool hit = crossings == 0 && first ? (h = *first).hit() : scene.accel.intersect(r, h);
        if (hit && !scene.shapes[h.geom_id].null_surface) return Spectrum(0.f);
        SurfaceInteraction si;
        if (hit) scene.fill_hit(r, h, si, false);
        if (m >= 0) {
            Ray seg = r;
            seg.tmax = hit ? si.t : r.tmax;
            tr *= transmittance(scene.media[size_t(m)], seg, ps.uniform_channels ? Spectrum(1.f) : beta, u);
            if (tr.is_black()) return tr;
        }
        if (!hit) return tr;
        m = medium_after(ps, si, r.d, m);
        r = finite ? si.spawn_ray_to(end, Normal3f(0.f), Vec3f(0.f)) : si.spawn_ray(r.d);
    }
    return Spectrum(0.f);  // a path through 256 null boundaries: treated as blocked
}

int32_t subsurface_entry(const PathSetup& ps, const SurfaceInteraction& si, const BxDFSample& s) {
    const Scene& scene = *ps.scene;
    const int32_t ss = si.shape_id < scene.shape_subsurface.size() ? scene.shape_subsurface[si.shape_id] : -1;
    if (ss < 0 || !has_flag(s.lobe, BxDFFlags::Transmission)) return -1;
    return dot(si.wo, si.ng) > 0.f && dot(s.wi, si.ng) < 0.f ? ss : -1;
}

bool subsurface_probe(const PathSetup& ps, int32_t ss, const SurfaceInteraction& si, PCG32& rng, BxDFSample* s,
                      SurfaceInteraction* exit) {
    // Textured parameters give the hit its own profiles (built here, on the stack).
    const SeparableBSSRDF& shared = ps.scene->subsurface[size_t(ss)];
    const SeparableBSSRDF b = ps.scene->has_textures ? bssrdf_at(*ps.scene, shared, si) : shared;
    const float u_axis = rng.next_float();
    const Vec2f u(rng.next_float(), rng.next_float());
    const float u_hit = rng.next_float();
    Spectrum w;
    if (!sample_probe(*ps.scene, b, si, u_axis, u, u_hit, exit, &w)) return false;
    s->weight *= w * entry_weight_scale(b);
    s->eta = 1.f;
    return s->weight.is_finite() && !s->weight.is_black();
}

Spectrum subsurface_exit_eval(const PathSetup& ps, int32_t ss, const SurfaceInteraction& si, const Vec3f& wi, float* pdf) {
    return ps.scene->subsurface[size_t(ss)].exit_eval(si.shading.to_local(wi), pdf);
}

bool subsurface_exit_sample(const PathSetup& ps, int32_t ss, const SurfaceInteraction& si, Vec2f u, BxDFSample* out) {
    if (!ps.scene->subsurface[size_t(ss)].exit_sample(u, out)) return false;
    out->wi = si.shading.to_world(out->wi);
    return true;
}

uint64_t film_add_pixel(Film& film, int x, int y, FilmSample* s, int n) {
    int kept = 0;
    for (int i = 0; i < n; ++i)
        if (valid_sample<SampleValues::NonNegative>(s[i].L)) s[kept++] = s[i];
    film.splat_pixel(x, y, s, kept);
    return uint64_t(n - kept);
}
}  // namespace path_services
}  // namespace pellucid
