// The BxDF testing surface: pellucid._core.BSDFProbe, vectorised over (N, 3) float32 arrays in
// the local shading frame; and the same for phase functions (pellucid._core.PhaseProbe). All loops live in pellucid_core (bxdf/batch.h); this file only checks
// shapes, allocates outputs and releases the GIL.
// SPDX-License-Identifier: Apache-2.0
#include "bind.h"
#include "pellucid/material/bsdf_probe.h"
#include "pellucid/medium/phase_batch.h"
#include "pellucid/util/error.h"

namespace pellucid::bind {
namespace {
using FArr = py::array_t<float, py::array::c_style | py::array::forcecast>;

size_t rows3(const FArr& a, const char* name) {
    if (a.ndim() != 2 || a.shape(1) != 3)
        throw Error(std::string(name) + ": expected an array of shape (N, 3), got shape " + shape_text(a));
    return size_t(a.shape(0));
}
size_t rows_pair(const FArr& a, const char* an, const FArr& b, const char* bn) {
    size_t n = rows3(a, an);
    if (rows3(b, bn) != n)
        throw Error(std::string(an) + " and " + bn + ": expected the same number of rows, got shapes " + shape_text(a) +
                    " and " + shape_text(b));
    return n;
}
py::array_t<float> empty(size_t n, bool vec3) {
    return vec3 ? py::array_t<float>({py::ssize_t(n), py::ssize_t(3)}) : py::array_t<float>(py::ssize_t(n));
}

py::array_t<float> eval(const BSDFProbe& p, const FArr& wo, const FArr& wi) {
    size_t n = rows_pair(wo, "wo", wi, "wi");
    py::array_t<float> f = empty(n, true);
    float* out = f.mutable_data();
    py::gil_scoped_release nogil;
    eval_batch(p.bxdf, p.ctx, wo.data(), wi.data(), n, out);
    return f;
}
py::array_t<float> pdf(const BSDFProbe& p, const FArr& wo, const FArr& wi) {
    size_t n = rows_pair(wo, "wo", wi, "wi");
    py::array_t<float> r = empty(n, false);
    float* out = r.mutable_data();
    py::gil_scoped_release nogil;
    pdf_batch(p.bxdf, p.ctx, wo.data(), wi.data(), n, out);
    return r;
}
py::tuple sample(const BSDFProbe& p, const FArr& wo, const FArr& u) {
    size_t n = rows_pair(wo, "wo", u, "u");
    py::array_t<float> wi = empty(n, true), w = empty(n, true), pd = empty(n, false);
    py::array_t<uint32_t> lobe{py::ssize_t(n)};
    float *wi_p = wi.mutable_data(), *w_p = w.mutable_data(), *pd_p = pd.mutable_data();
    uint32_t* l_p = lobe.mutable_data();
    {
        py::gil_scoped_release nogil;
        sample_batch(p.bxdf, p.ctx, wo.data(), u.data(), n, wi_p, w_p, pd_p, l_p);
    }
    return py::make_tuple(wi, w, pd, lobe);
}
py::array_t<float> albedo(const BSDFProbe& p, const FArr& wo, int n_samples, uint64_t seed, int threads) {
    size_t n = rows3(wo, "wo");
    if (n_samples < 1) throw Error("n_samples: value " + std::to_string(n_samples) + " must be >= 1");
    py::array_t<float> a = empty(n, true);
    float* out = a.mutable_data();
    py::gil_scoped_release nogil;
    albedo_batch(p.bxdf, p.ctx, wo.data(), n, n_samples, seed, out, threads);
    return a;
}
py::dict benchmark(const BSDFProbe& p, int64_t n) {
    if (n < 1) throw Error("n: value " + std::to_string(n) + " must be >= 1");
    BxDFTiming t;
    {
        py::gil_scoped_release nogil;
        t = benchmark_bxdf(p.bxdf, p.ctx, size_t(n));
    }
    py::dict d;
    d["ns_eval"] = t.ns_eval;
    d["ns_pdf"] = t.ns_pdf;
    d["ns_sample"] = t.ns_sample;
    return d;
}
// ---- phase functions (medium/phase.h) ------------------------------------------------------------
struct PhaseProbe {
    PhaseFunction phase;
};
size_t rows2(const FArr& a, const char* name) {
    if (a.ndim() != 2 || a.shape(1) != 2)
        throw Error(std::string(name) + ": expected an array of shape (N, 2), got shape " + shape_text(a));
    return size_t(a.shape(0));
}
py::array_t<float> phase_eval(const PhaseProbe& p, const FArr& wo, const FArr& wi) {
    size_t n = rows_pair(wo, "wo", wi, "wi");
    py::array_t<float> r = empty(n, false);
    float* out = r.mutable_data();
    py::gil_scoped_release nogil;
    phase_eval_batch(p.phase, wo.data(), wi.data(), n, out);
    return r;
}
py::array_t<float> phase_pdf(const PhaseProbe& p, const FArr& wo, const FArr& wi) {
    size_t n = rows_pair(wo, "wo", wi, "wi");
    py::array_t<float> r = empty(n, false);
    float* out = r.mutable_data();
    py::gil_scoped_release nogil;
    phase_pdf_batch(p.phase, wo.data(), wi.data(), n, out);
    return r;
}
py::tuple phase_sample(const PhaseProbe& p, const FArr& wo, const FArr& u) {
    size_t n = rows3(wo, "wo");
    if (rows2(u, "u") != n)
        throw Error("wo and u: expected the same number of rows, got shapes " + shape_text(wo) + " and " + shape_text(u));
    py::array_t<float> wi = empty(n, true), w = empty(n, false), pd = empty(n, false);
    py::array_t<bool> delta{py::ssize_t(n)};
    float *wi_p = wi.mutable_data(), *w_p = w.mutable_data(), *pd_p = pd.mutable_data();
    bool* d_p = delta.mutable_data();
    {
        py::gil_scoped_release nogil;
        phase_sample_batch(p.phase, wo.data(), u.data(), n, wi_p, w_p, pd_p, d_p);
    }
    return py::make_tuple(wi, w, pd, delta);
}
}  // namespace

void bind_bxdf(py::module_& m) {
    py::class_<PhaseProbe>(m, "PhaseProbe", "One phase function (see pellucid.phase).")
        .def(py::init([](const py::dict& d) { return PhaseProbe{phase_from_desc(to_node(d, ""))}; }), py::arg("desc"))
        .def("eval", &phase_eval, py::arg("wo"), py::arg("wi"), "p(wo, wi) in 1/sr per row, (N,).")
        .def("pdf", &phase_pdf, py::arg("wo"), py::arg("wi"), "Solid-angle pdf of wi per row, (N,).")
        .def("sample", &phase_sample, py::arg("wo"), py::arg("u"), "(wi, weight, pdf, delta) for u = (u1, u2).")
        .def("__repr__", [](const PhaseProbe& p) { return to_string(p.phase); });
    py::class_<BSDFProbe>(m, "BSDFProbe", "One material's BxDF at a default hit (see pellucid.bsdf).")
        .def(py::init([](const py::dict& d, const std::string& mode) {
                 return BSDFProbe::from_desc(to_node(d, ""), mode);
             }), py::arg("desc"), py::arg("mode") = "radiance")
        .def("eval", &eval, py::arg("wo"), py::arg("wi"), "f·|cos θi| per row, (N, 3).")
        .def("pdf", &pdf, py::arg("wo"), py::arg("wi"), "Solid-angle pdf of wi per row, (N,).")
        .def("sample", &sample, py::arg("wo"), py::arg("u"), "(wi, weight, pdf, lobe) for u = (u_lobe, u1, u2).")
        .def("albedo", &albedo, py::arg("wo"), py::arg("n_samples"), py::arg("seed") = 1, py::arg("threads") = 0,
             "Mean sample weight per row of wo, (N, 3).")
        .def("benchmark", &benchmark, py::arg("n"), "Single-thread ns per eval/pdf/sample call.")
        .def_property_readonly("flags", [](const BSDFProbe& p) { return uint32_t(flags(p.bxdf)); })
        .def("__repr__", &BSDFProbe::to_string);
    py::dict f;
    for (auto [name, v] : {std::pair<const char*, BxDFFlags>{"reflection", BxDFFlags::Reflection},
                           {"transmission", BxDFFlags::Transmission}, {"diffuse", BxDFFlags::Diffuse},
                           {"glossy", BxDFFlags::Glossy}, {"specular", BxDFFlags::Specular}})
        f[name] = uint32_t(v);
    m.attr("BXDF_FLAGS") = f;
}
}  // namespace pellucid::bind
