// Diffusion profiles and the searchlight random walk (pellucid.bssrdf): pellucid._core.BSSRDFProfile,
// vectorised over float32 arrays, and the free functions of bssrdf/profile.h and bssrdf/searchlight.h.
// The loops live in pellucid_core; this file checks names, allocates outputs and releases the GIL.
// SPDX-License-Identifier: Apache-2.0
#include <pybind11/stl.h>

#include "bind.h"
#include "pellucid/bssrdf/profile.h"
#include "pellucid/bssrdf/searchlight.h"
#include "pellucid/util/error.h"

namespace pellucid::bind {
namespace {
using namespace pellucid::bssrdf;
using FArr = py::array_t<float, py::array::c_style | py::array::forcecast>;

Diffusion model_of(const std::string& name) {
    Diffusion m;
    if (!parse_diffusion(name, &m)) throw Error("model: unknown diffusion model '" + name + "' (known: dipole, better_dipole)");
    return m;
}

template <class Fn>
py::array_t<float> map(const FArr& in, Fn&& fn) {
    py::array_t<float> out(std::vector<py::ssize_t>(in.shape(), in.shape() + in.ndim()));
    float* o = out.mutable_data();
    const float* i = in.data();
    const size_t n = size_t(in.size());
    py::gil_scoped_release nogil;
    fn(i, n, o);
    return out;
}

template <class V>
py::array_t<V> array_of(const std::vector<V>& v) {
    return py::array_t<V>(py::ssize_t(v.size()), v.data());
}

py::dict run_searchlight(const SearchlightSetup& s) {
    SearchlightResult r;
    {
        py::gil_scoped_release nogil;
        r = searchlight(s);
    }
    py::dict d;
    d["photons"] = r.photons;
    d["reflectance"] = r.reflectance;
    d["transmittance"] = r.transmittance;
    d["absorbed"] = r.absorbed;
    d["lost"] = r.lost;
    d["reflectance_single"] = r.reflectance_single;
    d["mean_collisions"] = r.mean_collisions;
    d["exitance"] = array_of(r.exitance);
    d["exitance_single"] = array_of(r.exitance_single);
    d["counts"] = array_of(r.counts);
    d["counts_single"] = array_of(r.counts_single);
    d["chunk_reflectance"] = array_of(r.chunk_reflectance);
    return d;
}
}  // namespace

void bind_bssrdf(py::module_& m) {
    py::class_<Profile>(m, "BSSRDFProfile", "One colour channel's diffusion profile (see pellucid.bssrdf.profile).")
        .def(py::init([](const std::string& model, float sa, float ss, float g, float eta) {
                 return Profile::make(model_of(model), sa, ss, g, eta);
             }),
             py::arg("model"), py::arg("sigma_a"), py::arg("sigma_s"), py::arg("g"), py::arg("eta"))
        .def("eval", [](const Profile& p, const FArr& r) { return map(r, [&](auto i, auto n, auto o) { eval_batch(p, i, n, o); }); },
             py::arg("r"), "R(r) in 1/length², elementwise.")
        .def("pdf", [](const Profile& p, const FArr& r) { return map(r, [&](auto i, auto n, auto o) { pdf_batch(p, i, n, o); }); },
             py::arg("r"), "Density of sample() per unit area at radius r, elementwise.")
        .def("sample", [](const Profile& p, const FArr& u) { return map(u, [&](auto i, auto n, auto o) { sample_batch(p, i, n, o); }); },
             py::arg("u"), "Radii for u in [0, 1), elementwise.")
        .def_property_readonly("total", &Profile::total)
        .def_property_readonly("r_max", &Profile::r_max)
        .def_property_readonly("diffusion_length", &Profile::diffusion_length)
        .def_property_readonly("mean_free_path", &Profile::mean_free_path)
        .def_property_readonly("reduced_albedo", &Profile::reduced_albedo)
        .def_property_readonly("model", [](const Profile& p) { return std::string(to_string(p.model())); });
    m.def("bssrdf_from_diffuse",
          [](const std::string& model, float albedo, float mfp, float g, float eta) {
              float sa = 0.f, ss = 0.f;
              if (!from_diffuse(model_of(model), albedo, mfp, g, eta, &sa, &ss))
                  throw Error("from_diffuse: no coefficients for albedo " + std::to_string(albedo) + ", mfp " + std::to_string(mfp) +
                              ", g " + std::to_string(g) + ", eta " + std::to_string(eta) +
                              " (albedo in [0, 1), mfp > 0, g in [-1, 1), eta > 0)");
              return py::make_tuple(sa, ss);
          },
          py::arg("model"), py::arg("albedo"), py::arg("mfp"), py::arg("g"), py::arg("eta"), "(sigma_a, sigma_s) of a diffuse albedo and mean free path.");
    m.def("bssrdf_total", [](const std::string& model, double alpha_p, double eta) { return total_of_reduced_albedo(model_of(model), alpha_p, eta); },
          py::arg("model"), py::arg("reduced_albedo"), py::arg("eta"), "The profile's total for a reduced albedo.");
    m.def("fresnel_moment", &fresnel_moment, py::arg("i"), py::arg("eta"), py::arg("internal"), "C_i = ∫0^1 F(μ) μ^i dμ.");
    m.def("exit_lobe_norm", &exit_lobe_norm, py::arg("eta"), "c = 1 − 2 C1(eta, external).");
    m.def("bssrdf_searchlight",
          [](float sa, float ss, float g, float eta, double thickness, int64_t photons, uint64_t seed, std::vector<double> r_edges,
             int64_t max_collisions, int threads) {
              return run_searchlight(SearchlightSetup{sa, ss, g, eta, thickness, photons, seed, std::move(r_edges), max_collisions, threads});
          },
          py::arg("sigma_a"), py::arg("sigma_s"), py::arg("g"), py::arg("eta"), py::arg("thickness"), py::arg("photons"), py::arg("seed"),
          py::arg("r_edges"), py::arg("max_collisions"), py::arg("threads"), "The searchlight random walk (see pellucid.bssrdf.searchlight).");
}
}  // namespace pellucid::bind
