// What the templated path tracer (integrator/path_kernel.h) does one lane at a time: the parts of a
// vertex that have no packet form yet (BSDFs other than the packet Lambertian, light sampling,
// emission, camera rays, ray differentials, the samplers). They are plain functions compiled once,
// for the baseline instruction set: the per-target kernels call them and never instantiate scalar
// code of their own, so no function of the library exists in two instruction sets under one name.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "pellucid/bxdf/bsdf.h"
#include "pellucid/geometry/interaction.h"
#include "pellucid/image/film.h"
#include "pellucid/integrator/render_loop.h"
#include "pellucid/light/area.h"
#include "pellucid/light/light_table.h"
#include "pellucid/light/light_types.h"
#include "pellucid/medium/medium.h"
#include "pellucid/sampling/rng.h"
#include "pellucid/sampling/sampler.h"
#include "pellucid/texture/texture_lanes.h"

namespace pellucid {
class Scene;

/// What the path tracer reads of a scene and its settings, prepared once per render.
/// The models the path tracer shades as packets (their templates XT<F>), and kBSDFLane.
enum PacketKind : int32_t {
    kBSDFLane = 0,
    kPacketLambertian = 1,
    kPacketSmoothDielectric = 2,
    kPacketSmoothConductor = 3,
    kPacketRoughConductor = 4,
    kPacketPlastic = 5,  ///< smooth or GGX rough plastic (RoughPlasticT, plastic_lanes)
    kPacketRoughConductorBeckmann = 6,
    kPacketPlasticBeckmann = 7,  ///< rough plastic over Beckmann (RoughPlasticT<F, BeckmannT<F>>)
    kPacketRoughDielectric = 8,  ///< GGX rough dielectric without multiple scattering (RoughDielectricT)
    kPacketRoughDielectricBeckmann = 9,
    kPacketPrincipled = 10,  ///< opaque solid principled BSDF, Burley 2015 (PrincipledBSDFT, principled_lanes)
    kPacketThinDielectric = 11,  ///< ThinDielectricT (a delta form; parameters as the smooth dielectric's)
    kPacketOrenNayar = 12,       ///< classic or EON Oren–Nayar (OrenNayarT, oren_nayar_packet_params)
    kPacketPrincipled2012 = 13,  ///< principled BRDF, Burley 2012 (Principled2012T, principled2012_lanes)
    kPacketPrincipledThin = 14,  ///< thin-sheet principled BSDF, Burley 2015 (PrincipledThinT, principled_thin_lanes)
    kPacketPrincipledSolid = 15,  ///< principled solid with a transmission lobe (PrincipledSolidT, principled_solid_lanes)
};
constexpr int kPacketParams = 20;

#if PELLUCID_DISPATCH_STATS
/// The diagnostic build's counters (CMake PELLUCID_DISPATCH_STATS; bench/dispatch_stats.py): one
/// masked call of packet form `kind` (kind −1: one tile of the kernel; −2: one packet pass, its lanes
/// those that go on from a hit) ran on a packet of
/// `width` lanes, `lanes` of them its own, in `cycles` time stamp-counter cycles. The totals are
/// printed to standard error when the process exits, one line per form:
/// "dispatch form K calls C lanes N width W cycles T".
void dispatch_record(int kind, int lanes, int width, uint64_t cycles);
uint64_t dispatch_clock();
#endif
/// How many parameters the packet form of `kind` reads (0 for kBSDFLane).
int packet_param_count(int32_t kind);

/// The longest path an unbounded max_depth (-1) allows, in vertices (docs/rendering.md).
constexpr int kUnboundedDepth = 1 << 16;

struct PathSetup {
    const Scene* scene = nullptr;
    int max_depth = kUnboundedDepth;  ///< longest path in segments ("direct" = 2; unbounded = kUnboundedDepth)
    int rr_depth = 5;
    bool use_nee = true, use_mis = true;
    SamplerType sampler = SamplerType::Independent;
    /// Per material: which packet form shades its lanes (PacketKind), where its BSDF is the same at
    /// every hit (untextured, two-sided, no bump or normal map) and its model has one; else
    /// kBSDFLane (the lane goes through BSDF, one at a time).
    std::vector<int32_t> packet_kind;
    /// Per material, kPacketParams floats: the packet form's parameters (Lambertian: reflectance;
    /// smooth and thin dielectrics: η, reflectance, transmittance; Oren–Nayar:
    /// oren_nayar_packet_params; conductors: η, k, specular_reflectance,
    /// then for the rough ones (GGX, Beckmann) αx, αy and 1 for separable shadowing; plastics:
    /// plastic_packet_params; principled: principled_packet_params or, for the 2012 model,
    /// principled2012_packet_params), and its BxDFFlags. kPacketParamsPad zeros follow the last
    /// material's, so that a row may be read as 16 + 8 floats (lane::gather_rows).
    static constexpr int kPacketParamsPad = 8;
    std::vector<float> packet_params;
    /// Per material, how many of its kPacketParams its packet form reads (packet_param_count); a
    /// lane copies only those (the forms of other kinds ignore the lane's values: they select their
    /// own lanes' parameters).
    std::vector<int32_t> packet_count;
    int max_packet_count = 0;  ///< the largest packet_count (what the table lanes gather)
    std::vector<uint32_t> packet_flags;
    /// Per material: built at each hit (textured, or with a bump or normal map) and shaded by its
    /// model's packet form wherever the BSDF built there has one (path_services::packet_form).
    std::vector<uint8_t> textured_packet;
    /// Per material built at each hit whose model is a plastic with a rough coat: the coat's table,
    /// which every hit's BSDF shares (its α and η are not textured), and the table's offset in
    /// coat_tables; null and 0 for the others (packet_form).
    std::vector<const RoughCoatTable*> textured_coat;
    std::vector<float> textured_coat_offset;
    /// Per material: its entry in tex_lanes, or −1. A two-sided material built at each hit whose
    /// textures the packet pass evaluates itself, from the hit's full record, for all its lanes at
    /// once (texture/texture_lanes.h): a Lambertian, or a rough plastic (GGX or Beckmann) with only
    /// its diffuse reflectance textured; that texture a constant, an image kept in memory looked up
    /// bilinearly with the Repeat wrap, or a point-sampled checkerboard (the colour of the hit's
    /// square, checkerboard_square); without a normal map; its
    /// bump map, if any, of BumpModel::Mitsuba from such an image or a constant, with
    /// InvalidNormals::Mirror or Keep; in a scene that reads no pixel footprints. Its hits on the
    /// shape tables are vertex lanes, their uv and tangents from tri_uv or the sphere's vertex (the
    /// sphere's uv one lane at a time, sphere_uv); elsewhere they take full records. Its lanes get the
    /// parameters, frame and softened terminator of the BSDF Scene::textured_bsdf builds there, bit
    /// for bit; the other textured materials build their BSDF one lane at a time.
    struct TexLaneMaterial {
        enum Source : uint8_t { kConstant, kImage, kChecker };
        int32_t kind = kPacketLambertian;  ///< kPacketLambertian, kPacketPlastic or kPacketPlasticBeckmann
        /// A plastic's packet parameters but for Kd's (plastic_packet_params), and its η, R̄ and
        /// variant (plastic_diffuse_scale).
        float q[kPacketParams] = {};
        float eta = 1.f, rbar = 0.f;
        PlasticVariant variant = PlasticVariant::Coupled;
        Source reflectance = kConstant;  ///< the Lambertian's reflectance, or the plastic's Kd
        float albedo[2][3] = {};  ///< constant: albedo[0]; checker: color0's and color1's, clamped as TexEval
        float lo = 0.f, hi = 1.f;  ///< an image's clamp (Tex::lo, hi)
        LaneImage image;           ///< the reflectance image
        float to_uv[6] = {1.f, 0.f, 0.f, 0.f, 1.f, 0.f};  ///< its (or the checkerboard's) to_uv: a00, a01, b0, a10, a11, b1
        bool bump = false, bump_image = false;  ///< a bump map; from an image (else a constant: no gradient)
        LaneImage height;
        float height_uv[6] = {1.f, 0.f, 0.f, 0.f, 1.f, 0.f};
        float bump_scale = 1.f;
        bool mirror = false;                    ///< InvalidNormals::Mirror (else Keep)
        bool soften = false, estevez = false;   ///< its terminator softened (MaterialTextures), and by which model
    };
    std::vector<int32_t> tex_lane;
    std::vector<TexLaneMaterial> tex_lanes;
    bool tex_tangents = false;  ///< some of tex_lanes has a bump map (reads the hit's ∂p/∂u, ∂p/∂v)
    /// One-channel copies of the grey three-channel images tex_lanes read (every texel's three
    /// floats equal: the lookups' three channels are then the one's, bit for bit, from a third of
    /// the gathers and memory), which their LaneImages point into.
    struct GreyImage {
        const float* source;                               ///< the image's texels (ImageTextureHandle)
        std::shared_ptr<const std::vector<float>> texels;  ///< its one channel
    };
    std::vector<GreyImage> grey_images;
    /// The flat triangles whose hits the kernel records as packets (gathered by triangle; the
    /// others' lanes fetch one at a time, scene/hit_packets.h): tri_base[g] is mesh geometry g's
    /// first triangle in tri_table, or −1 (a sphere, interpolated normals, an emitter, more than
    /// kMaxTriangleTable triangles in all, a scene with media or subsurface scattering). Each
    /// triangle is kTriStride floats: corners p0, p1, p2, geometric normal, shading frame s, t, n,
    /// and its material as an int32's bits, −1 where that material needs the full hit record
    /// (no packet form, or a delta lobe in a scene that carries ray differentials).
    static constexpr int kTriStride = 24;
    static constexpr size_t kMaxTriangleTable = size_t(1) << 20;
    std::vector<int32_t> tri_base;
    std::vector<float> tri_table;
    /// With tex_lanes: the uvs of the triangle table's triangles as fill_hit
    /// interpolates them, and their tangents (kTriUVStride floats per triangle: uv0, uv1, uv2, with
    /// (0, 0), (1, 0), (1, 1) for a mesh without uvs; two unused; ∂p/∂u, ∂p/∂v as FlatTriangle has
    /// them; two unused), else empty.
    static constexpr int kTriUVStride = 16;
    std::vector<float> tri_uv;
    /// Some mesh outside the triangle table has more than kPrefetchTriangles triangles: the kernel
    /// requests its hits' index rows as soon as the hits are known, and their vertices before the
    /// records are made (prefetch_index_rows, prefetch_vertices in scene/hit_packets.h).
    bool prefetch_hits = false;
    /// The spheres likewise (gathered by geometry): sphere_row[g] is sphere geometry g's row in
    /// sphere_table, or −1 (a mesh, an emitter, a scene with media or subsurface scattering). Each
    /// row is kSphereStride floats: centre, radius, rotation columns (ShapeRecord::rotation), 1
    /// where the normals are flipped, and the material as tri_table holds it.
    static constexpr int kSphereStride = 16;
    std::vector<int32_t> sphere_row;
    std::vector<float> sphere_table;
    /// The rough coats' transmittance tables of the packet plastics, one after another
    /// (RoughCoatTable::values; a plastic's parameters hold its table's offset).
    std::vector<float> coat_tables;
    /// NEE's triangles when every light is an area light on a mesh (light/area.h), else empty:
    /// then lights are sampled one lane at a time (path_services::sample_light).
    EmitterTable emitters;
    /// Without an emitter table: the lights NEE samples as packets (sphere area lights, constant
    /// environments, environment maps; light/light_table.h), once a lane has picked one
    /// (path_services::pick_light), and the lights at infinity that escaping rays see.
    LightTable lights;
    /// The scene has media or null boundaries (medium/medium.h): paths track the medium they are
    /// in, which starts as camera_medium (-1: none).
    bool media = false;
    int32_t camera_medium = -1;
    /// Per medium: 1 for a homogeneous one, whose lanes the kernel's distance sampling takes as
    /// packets (homogeneous_step), else 0; and its row of medium_rows: kMediumStride floats, σt (σa
    /// + σs), σs and Le (zeros for the others). any_homogeneous: some medium is.
    static constexpr int kMediumStride = 16;
    std::vector<int32_t> homogeneous_media;
    std::vector<float> medium_rows;
    bool any_homogeneous = false;
    bool medium_nee = true;        ///< NEE at medium collisions (integrator.medium_nee)
    bool uniform_channels = false; ///< channel_sampling "uniform": each colour channel 1/3, else ∝ throughput
    /// Some shape renders with a diffusion BSSRDF (Scene::subsurface): paths that refract into it
    /// leave at an exit point found by probe rays (bssrdf/separable.h).
    bool subsurface = false;
};
PathSetup make_path_setup(const Scene& scene, int max_depth, int rr_depth, bool use_nee, bool use_mis, SamplerType type);

/// Random numbers of one vertex, in path.cpp's sample-dimension layout: u[0..2] light selection
/// and point (drawn when nee), u[3..5] lobe and direction, u[6] roulette (drawn when roulette).
struct VertexRandoms {
    float u[7];
};

namespace path_services {
/// Start sample `sample` of pixel (x, y): its sampler and its film position (fx, fy), given the
/// pixel's share of the seeding (pixel_seed). The kernel makes the camera ray through (fx, fy)
/// (PerspectiveCamera::direction).
void start_sample(const PathSetup& ps, bool splat, int x, int y, int sample, const Sampler::PixelSeed& px, Sampler* sampler,
                  float* fx, float* fy);
/// start_sample for n samples of the independent sampler on a splatting film, side by side (eight
/// streams at a time where N is a multiple of 8, PCG32x8; the path kernel starts a
/// packet's paths with it): sample `sample[i]`
/// of the pixel whose stream is `stream[i]` (PixelSeed::stream) and whose centre is (cx[i],
/// cy[i]) gets the film position (fx[i], fy[i]) and the PCG32 state and increment its sampler has
/// after get_pixel_2d() (Sampler::independent_after_pixel).
template <int N>
[[gnu::always_inline]] inline void start_independent_samples(const uint64_t* stream, const uint64_t* sample, const float* cx,
                                                             const float* cy, uint64_t* state, uint64_t* inc, float* fx,
                                                             float* fy) {
    if constexpr (N % 8 == 0) {  // eight streams at a time (PCG32x8: the same bits)
        using X = PCG32x8;
        using X4 = PCG32x4;
        for (int b = 0; b < N; b += 8) {
            X::State s[2], c[2];
            for (int h = 0; h < 2; ++h) {
                const X::State st = X4::load<X::State>(stream + b + 4 * h), smp = X4::load<X::State>(sample + b + 4 * h);
                c[h] = (st << 1u) | 1u;                              // increment_of
                s[h] = X4::mix_bits(smp ^ (st << 1u));               // sample_init
                s[h] = X4::step(X4::step(X::State{}, c[h]) + s[h], c[h]);  // seeded_state
            }
            const X::F32 u0 = X::to_float(X::output(s[0], s[1]));
            for (int h = 0; h < 2; ++h) s[h] = X4::step(s[h], c[h]);
            const X::F32 u1 = X::to_float(X::output(s[0], s[1]));
            for (int h = 0; h < 2; ++h) X4::store(state + b + 4 * h, X4::step(s[h], c[h])), X4::store(inc + b + 4 * h, c[h]);
            // film_position with a splatting film: the pixel's corner + 0.5 + (u - 0.5).
            X::store(fx + b, X::load<X::F32>(cx + b) + (u0 - 0.5f)), X::store(fy + b, X::load<X::F32>(cy + b) + (u1 - 0.5f));
        }
        return;
    }
    for (int i = 0; i < N; ++i) {
        const uint64_t c = PCG32::increment_of(stream[i]);
        uint64_t s = PCG32::seeded_state(PCG32::sample_init(stream[i], sample[i]), c);
        const float u0 = PCG32::to_float(PCG32::output(s));
        s = PCG32::step(s, c);
        const float u1 = PCG32::to_float(PCG32::output(s));
        state[i] = PCG32::step(s, c), inc[i] = c;
        // film_position with a splatting film: the pixel's corner + 0.5 + (u - 0.5).
        fx[i] = cx[i] + (u0 - 0.5f), fy[i] = cy[i] + (u1 - 0.5f);
    }
}
/// The part of a sample's Sampler that every sample of pixel (x, y) shares (Sampler::PixelSeed).
Sampler::PixelSeed pixel_seed(const PathSetup& ps, int x, int y, uint64_t seed);
/// Trace n ≤ 16 rays, given as arrays (soa = origin x, y, z, direction x, y, z, tmax), where
/// valid[i] (one Embree packet when n > 1; EmbreeScene::intersect_lanes); hit[i]: ray i was traced
/// and hit. The kernel's hits: Scene::fill_hit or scene/hit_packets.h make them records.
void trace_lanes(const Scene& scene, int n, const float* const soa[7], const bool* valid, HitLanes& h, bool* hit);
/// Whether each of n ≤ 16 rays, given as arrays, is blocked (EmbreeScene::occluded_lanes; one ray
/// traced alone when n is 1), where valid[i].
void occluded_lanes(const Scene& scene, int n, const float* const soa[7], const bool* valid, bool* blocked);
/// Radiance from the lights at infinity seen along the escaping direction d, MIS-weighted.
Spectrum escaped(const PathSetup& ps, const LightSampleContext& prev, const Vec3f& d, bool specular, float prev_pdf);
/// Emission of the surface hit si toward the ray's origin, and NEE's density for it (0 after a
/// delta bounce).
Spectrum emitted(const PathSetup& ps, const SurfaceInteraction& si, const LightSampleContext& prev, const Vec3f& d,
                 bool specular, float* light_pdf);
/// Set si's pixel footprint from the ray (Scene::compute_footprint).
void footprint(const PathSetup& ps, SurfaceInteraction& si, const RayDifferential& ray);
/// The BSDF at si (footprint set first when the scene has textures), built into *out; its flags.
BxDFFlags bsdf_begin(const PathSetup& ps, SurfaceInteraction& si, const RayDifferential& ray, BSDF* out);
/// The packet form of a BSDF built at a hit of material m and its parameters into q (kPacketParams
/// floats), or kBSDFLane (no form for its model or parameters, or a plastic whose rough coat's table
/// is not the material's, PathSetup::textured_coat). The BSDF's frame and its terminator softening
/// (BSDF::softens, terminator_factor) go with it.
int32_t packet_form(const PathSetup& ps, uint32_t m, const BSDF& b, float* q);
Spectrum bsdf_eval(const BSDF& bsdf, const Vec3f& wo, const Vec3f& wi, float* pdf);
bool bsdf_sample(const BSDF& bsdf, const Vec3f& wo, float u_lobe, Vec2f u, BxDFSample* out);
/// Draw one vertex's random numbers.
void randoms(Sampler& sampler, int depth, bool nee, bool roulette, VertexRandoms* out);
/// NEE: pick a light and a point on it; *shadow is the ray toward it. False: no sample.
bool sample_light(const PathSetup& ps, const SurfaceInteraction& si, float u_sel, Vec2f u, LightLiSample* ls,
                  float* light_pdf, Ray* shadow);
/// NEE's choice of a light with u_sel (Scene::sample_light); *pmf receives its probability.
int32_t pick_light(const PathSetup& ps, float u_sel, float* pmf);
/// sample_light for the light li that pick_light chose with probability pmf.
bool sample_picked_light(const PathSetup& ps, const SurfaceInteraction& si, int32_t li, float pmf, Vec2f u,
                         LightLiSample* ls, float* light_pdf, Ray* shadow);
/// The ray leaving si in direction wi (with differentials through a delta bounce when textures
/// need them).
RayDifferential next_ray(const PathSetup& ps, const SurfaceInteraction& si, const RayDifferential& in, const Vec3f& wi,
                         bool specular, bool transmission, float eta);
/// Hand one finished estimate to the film; false if it was rejected.
// ---- media (medium/medium.h, docs/media.md) ----------------------------------------------------
/// The random numbers of one path's medium events: a stream of its own per (pixel, sample, seed),
/// apart from the sampler's dimensions, since tracking draws an unbounded number of them.
PCG32 medium_rng(const PathSetup& ps, int x, int y, int sample, uint64_t seed);
/// Whether si lies on a `null` boundary, which a path crosses unchanged.
bool is_null_surface(const PathSetup& ps, const SurfaceInteraction& si);
/// The medium a path is in after leaving si in direction w: the shape's interior (w against the
/// geometric normal) or exterior where the shape bounds media, else `current`.
int32_t medium_after(const PathSetup& ps, const SurfaceInteraction& si, const Vec3f& w, int32_t current);
/// Distance sampling over the segment [0, ray.tmax) of medium m (sample_distance).
MediumEvent medium_sample(const PathSetup& ps, int32_t m, const Ray& ray, const Spectrum& beta, PCG32& rng);
/// The vertex of a collision at ray.o + t·ray.d: an interaction with no surface (zero normal and
/// error bound, so rays leave from the point itself), wo = −ray.d normalised.
void medium_vertex(const Ray& ray, float t, SurfaceInteraction* out);
/// The ray that goes on through a `null` boundary at si in direction d.
RayDifferential cross_boundary(const SurfaceInteraction& si, const Vec3f& d);
/// The phase function of medium m in place of a BSDF: its value (= its density, no cosine) and
/// a sampled direction (lobe DiffuseReflection, or SpecularReflection for the delta of |g| = 1).
Spectrum phase_eval(const PathSetup& ps, int32_t m, const Vec3f& wo, const Vec3f& wi, float* pdf);
bool phase_sample(const PathSetup& ps, int32_t m, const Vec3f& wo, Vec2f u, BxDFSample* out);
/// Transmittance of a shadow ray that starts in medium m (-1: none): through `null` boundaries,
/// where the medium changes, and 0 at any other surface. `first`, where given, is the ray's first
/// hit (or miss: geom_id ~0u) as the kernel's packet traced it, in place of tracing it here.
Spectrum shadow_transmittance(const PathSetup& ps, int32_t m, const Ray& shadow, const Spectrum& beta, PCG32& rng,
                              const RayHit* first = nullptr);

// ---- subsurface scattering (bssrdf/separable.h, docs/subsurface.md) ---------------------------
/// The diffusion BSSRDF (index into Scene::subsurface) that a BSDF sample s at si enters: s refracts
/// from the outside (wo on the side of the geometric normal) into a shape rendered with one; else -1.
int32_t subsurface_entry(const PathSetup& ps, const SurfaceInteraction& si, const BxDFSample& s);
/// Probe for the exit point of BSSRDF ss from the entry si (random numbers from rng): *exit is the
/// exit's vertex, and s's weight becomes the entry's (1 − F) times Sp/pdf (s.eta 1, as the exit
/// undoes the refraction's radiance scaling). False: no exit (the path ends).
bool subsurface_probe(const PathSetup& ps, int32_t ss, const SurfaceInteraction& si, PCG32& rng, BxDFSample* s,
                      SurfaceInteraction* exit);
/// The exit lobe Sw of BSSRDF ss at the exit vertex si, toward world direction wi (cosine
/// included), with its density; and a sampled direction (world).
Spectrum subsurface_exit_eval(const PathSetup& ps, int32_t ss, const SurfaceInteraction& si, const Vec3f& wi, float* pdf);
bool subsurface_exit_sample(const PathSetup& ps, int32_t ss, const SurfaceInteraction& si, Vec2f u, BxDFSample* out);

/// The n estimates of pixel (x, y), in sample order, handed to the film (Film::splat_pixel); NaN,
/// infinite or negative ones are dropped (render_loop.h film_add). Returns how many were dropped.
/// Reorders nothing, but overwrites s with the kept estimates.
uint64_t film_add_pixel(Film& film, int x, int y, FilmSample* s, int n);
}  // namespace path_services
}  // namespace pellucid
