// Scene queries: hit records from kernel hits.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/scene/scene.h"

#include <cmath>
#include <sstream>

#include "pellucid/geometry/hit_lanes.h"

namespace pellucid {
namespace {
void fill_triangle(const TriangleMesh& m, const RayHit& h, SurfaceInteraction& si) {
    uint32_t i0 = m.indices[3 * h.prim_id], i1 = m.indices[3 * h.prim_id + 1], i2 = m.indices[3 * h.prim_id + 2];
    const Point3f &p0 = m.positions[i0], &p1 = m.positions[i1], &p2 = m.positions[i2];
    float b1 = h.u, b2 = h.v, b0 = 1.f - b1 - b2;
    si.uv = m.uvs.empty() ? Vec2f(b1 + b2, b2) : b0 * m.uvs[i0] + b1 * m.uvs[i1] + b2 * m.uvs[i2];
    si.dndu = si.dndv = Vec3f(0.f);
    if (!m.flat.empty()) {  // flat shading: every other quantity is constant over the triangle
        const FlatTriangle& f = m.flat[h.prim_id];
        const HitVertexT<float> v = flat_triangle_vertex<float>(p0, p1, p2, b1, b2, f.ng, f.shading);
        si.p = v.p;
        si.p_error = v.p_error;
        si.ng = f.ng;
        si.dpdu = f.dpdu;
        si.dpdv = f.dpdv;
        si.shading = f.shading;
        return;
    }
    // Interpolated vertex normals (a mesh with normals that are not all equal per triangle).
    const Vec2f uv0 = m.uvs.empty() ? Vec2f(0, 0) : m.uvs[i0], uv1 = m.uvs.empty() ? Vec2f(1, 0) : m.uvs[i1],
                uv2 = m.uvs.empty() ? Vec2f(1, 1) : m.uvs[i2];
    const TriangleTangentsT<float> tri = triangle_tangents<float>(p0, p1, p2, uv0, uv1, uv2);
    const Normal3f zero(0.f);  // (a mesh never given its flat table has no normals either)
    const Normal3f &n0 = m.normals.empty() ? zero : m.normals[i0], &n1 = m.normals.empty() ? zero : m.normals[i1],
                   &n2 = m.normals.empty() ? zero : m.normals[i2];
    const HitVertexT<float> v = smooth_triangle_vertex<float>(p0, p1, p2, b1, b2, tri, n0, n1, n2);
    si.p = v.p;
    si.p_error = v.p_error;
    si.ng = v.ng;
    si.shading = v.shading;
    si.dpdu = tri.dpdu;
    si.dpdv = tri.dpdv;
    // ∂n/∂u, ∂n/∂v of the interpolated normal, by the same uv solve as dp/du (pbrt-v4 §6.5.3).
    const Vec3f n = b0 * n0 + b1 * n1 + b2 * n2;
    if (length2(n) > 0.f) {
        const Vec2f duv02 = uv0 - uv2, duv12 = uv1 - uv2;
        const float det = duv02.x * duv12.y - duv02.y * duv12.x;
        if (std::fabs(det) >= 1e-9f) {
            float inv = 1.f / det;
            Vec3f dn02 = m.normals[i0] - m.normals[i2], dn12 = m.normals[i1] - m.normals[i2];
            si.dndu = (duv12.y * dn02 - duv02.y * dn12) * inv;
            si.dndv = (duv02.x * dn12 - duv12.x * dn02) * inv;
        }
    }
}


}  // namespace

Vec2f sphere_uv(const Vec3f& l) {
    float phi = std::atan2(l.y, l.x);
    if (phi < 0.f) phi += 2.f * kPi;
    return Vec2f(phi * kInv2Pi, safe_acos(l.z) * kInvPi);
}

namespace {
/// A sphere's rotation as columns (hit_lanes.h).
Mat3T<float> columns(const Mat3f& R) { return {R[0], R[1], R[2]}; }

void fill_sphere(const ShapeRecord& s, const Ray& ray, const RayHit& h, SurfaceInteraction& si, bool with_uv) {
    SphereTangentsT<float> tan;
    const HitVertexT<float> v =
        sphere_vertex<float>(ray.o, ray.d, h.t, s.center, s.radius, columns(s.rotation), s.flip_normals, &tan);
    si.p = v.p;
    si.p_error = v.p_error;
    si.ng = v.ng;
    si.shading = v.shading;
    si.dpdu = tan.dpdu;
    si.dpdv = tan.dpdv;
    const Vec3f& l = tan.local;  // the hit in object space (unit length)
    si.uv = with_uv ? sphere_uv(l) : Vec2f(0.f);
    // n = (p − c)/r, so ∂n/∂u = (∂p/∂u)/r (negated with the normal when it is flipped).
    float sgn = s.flip_normals ? -1.f : 1.f;
    si.dndu = (sgn / s.radius) * si.dpdu;
    si.dndv = (sgn / s.radius) * si.dpdv;
}
}  // namespace

bool Scene::intersect(const Ray& ray, SurfaceInteraction& si, bool with_uv) const {
    RayHit h;
    h.t = ray.tmax;
    if (!accel.intersect(ray, h)) return false;
    fill_hit(ray, h, si, with_uv);
    return true;
}

// Not inlined, so that intersect and the path kernel fill hit records with the same instructions.
[[gnu::noinline]] void Scene::fill_hit(const Ray& ray, const RayHit& h, SurfaceInteraction& si, bool with_uv) const {
    const ShapeRecord& s = shapes[h.geom_id];
    if (s.kind == ShapeRecord::Kind::Mesh) {
        fill_triangle(meshes[s.mesh_index], h, si);
        si.t = h.t;
    } else {
        // The sphere's t is its double-precision root (EmbreeScene::add_sphere), the same for
        // single rays and packets.
        fill_sphere(s, ray, h, si, with_uv);
        si.t = h.t;
    }
    si.wo = -ray.d;
    si.shape_id = h.geom_id;
    si.prim_id = h.prim_id;
    si.material_id = s.face_materials.empty() ? s.material : s.face_materials[h.prim_id];
    si.light_id = s.light;
}

Spectrum Scene::emitted(const SurfaceInteraction& si) const {
    if (si.light_id < 0) return Spectrum(0.f);
    return std::get<AreaLight>(lights[size_t(si.light_id)]).L(si.ng, si.wo);
}

void Scene::compute_footprint(SurfaceInteraction& si, const RayDifferential& ray) const {
    if (si.differentials_from_ray(ray)) return;
    camera.approximate_dp_dxy(si.p, si.ng, &si.dpdx, &si.dpdy);
    si.uv_differentials_from_dp();
}

RayDifferential Scene::specular_differentials(const SurfaceInteraction& si, const RayDifferential& in, const Ray& out,
                                              bool transmission, float eta) const {
    RayDifferential r(out);
    if (!in.has_differentials) return r;
    // Igehy 1999 §3.3; in pbrt-v3's form (§10.1.3): with n the shading normal on wo's side,
    // ∂n/∂x = ∂n/∂u·∂u/∂x + ∂n/∂v·∂v/∂x and ∂(wo·n)/∂x = ∂wo/∂x·n + wo·∂n/∂x,
    //   reflection: ∂wi/∂x = −∂wo/∂x + 2[(wo·n)∂n/∂x + ∂(wo·n)/∂x·n]
    //   refraction: ∂wi/∂x = −η∂wo/∂x + [μ∂n/∂x + ∂μ/∂x·n], μ = η(wo·n) − |wi·n|,
    //               ∂μ/∂x = (η − η²(wo·n)/|wi·n|)·∂(wo·n)/∂x, with η = η_i/η_t = 1/eta.
    const Vec3f wo = si.wo, wi = out.d;
    Vec3f n = si.shading.n, dndx = si.dndu * si.dudx + si.dndv * si.dvdx, dndy = si.dndu * si.dudy + si.dndv * si.dvdy;
    Vec3f dwodx = -in.rx_d - wo, dwody = -in.ry_d - wo;
    if (dot(wo, n) < 0.f) {
        n = -n;
        dndx = -dndx;
        dndy = -dndy;
    }
    float won = dot(wo, n);
    float ddndx = dot(dwodx, n) + dot(wo, dndx), ddndy = dot(dwody, n) + dot(wo, dndy);
    if (!transmission) {
        r.rx_d = wi - dwodx + 2.f * (won * dndx + ddndx * n);
        r.ry_d = wi - dwody + 2.f * (won * dndy + ddndy * n);
    } else {
        float e = 1.f / eta, win = std::fabs(dot(wi, n));
        if (!(win > 0.f)) return r;
        float mu = e * won - win;
        float k = e - e * e * won / win;
        r.rx_d = wi - e * dwodx + (mu * dndx + k * ddndx * n);
        r.ry_d = wi - e * dwody + (mu * dndy + k * ddndy * n);
    }
    r.rx_o = si.p + si.dpdx;
    r.ry_o = si.p + si.dpdy;
    r.has_differentials = std::isfinite(r.rx_d.x + r.rx_d.y + r.rx_d.z + r.ry_d.x + r.ry_d.y + r.ry_d.z);
    return r;
}

BSDF Scene::textured_bsdf(const SurfaceInteraction& si) const {
    const MaterialTextures& mt = material_textures[si.material_id];
    const TextureEvalContext ctx = texture_eval_context(si);
    if (!mt.has_textured_params()) {  // only the normal is perturbed: the prebuilt BxDF
        const Frame frame = perturbed_shading_frame(mt, textures, ctx, si);
        BSDF b = BSDF::borrowing(&material_bxdfs[si.material_id], frame, si.ng);
        if (mt.terminator_softening) b.soften_terminator(si.shading.n, mt.terminator_model);
        return b;
    }
    BxDF bxdf = make_bxdf(materials[si.material_id], TexEval(textures, ctx));
    if (!mt.perturbs_normal()) return BSDF(bxdf, si.shading, si.ng);
    BSDF b(bxdf, perturbed_shading_frame(mt, textures, ctx, si), si.ng);
    if (mt.terminator_softening) b.soften_terminator(si.shading.n, mt.terminator_model);
    return b;
}

std::string Scene::to_string() const {
    std::ostringstream os;
    os << "Scene[source=" << source << ", film=" << width << "x" << height << ", spp=" << spp
       << ", shapes=" << shapes.size() << ", triangles=" << triangle_count << ", materials=" << materials.size()
       << ", lights=" << lights.size() << ", integrator=" << integrator.type << "(max_depth="
       << integrator.max_depth << ")]";
    return os.str();
}
}  // namespace pellucid
