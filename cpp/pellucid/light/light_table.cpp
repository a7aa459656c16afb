// The packet lights' table (light_table.h).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/light/light_table.h"

#include <algorithm>
#include <cstdint>

#include "pellucid/light/light.h"
#include "pellucid/util/error.h"

namespace pellucid {

template <class LightT>
LightTable make_light_table(const std::vector<LightT>& lights, const std::vector<float>& pmf) {
    LightTable t;
    t.data.assign(LightTable::kStride * lights.size() + LightTable::kPad, 0.f);
    t.idata.assign(LightTable::kIntStride * lights.size(), 0);
    t.kind.assign(lights.size(), LightTable::kNone);
    std::vector<const EnvmapLight*> maps;
    for (const auto& l : lights)
        if (const auto* e = std::get_if<EnvmapLight>(&l)) maps.push_back(e);
    // One map: its own buffer. Several: copies in one pool, so that one base serves every lane.
    if (maps.size() == 1) {
        t.env = maps[0]->data();
    } else if (maps.size() > 1) {
        size_t n = 0;
        for (const EnvmapLight* e : maps) n += e->data()->size();
        PELLUCID_CHECK(n < size_t(INT32_MAX), "environment maps too large for one light table");
        auto pool = std::make_shared<std::vector<float>>();
        pool->reserve(n);
        for (const EnvmapLight* e : maps) pool->insert(pool->end(), e->data()->begin(), e->data()->end());
        t.env = std::move(pool);
    }
    // The pick: running sums of the probabilities in float, the last set to 1 (u < 1 always
    // finds a light), and each index's last light of nonzero probability (the first one for the
    // indices before it).
    const size_t n = lights.size();
    t.pick_pmf.assign(n, 0.f);
    for (size_t i = 0; i < n && i < pmf.size(); ++i) t.pick_pmf[i] = std::max(0.f, pmf[i]);
    t.pick_cdf.assign(n + 1, 0.f);
    for (size_t i = 0; i < n; ++i) t.pick_cdf[i + 1] = t.pick_cdf[i] + t.pick_pmf[i];
    if (n > 0) t.pick_cdf[n] = 1.f;
    t.pick_nonempty.assign(n, 0);
    int32_t first = -1, last = -1;
    for (size_t i = 0; i < n; ++i)
        if (t.pick_pmf[i] > 0.f) {
            first = int32_t(i);
            break;
        }
    for (size_t i = 0; i < n; ++i) {
        if (t.pick_pmf[i] > 0.f) last = int32_t(i);
        t.pick_nonempty[i] = last >= 0 ? last : std::max(first, 0);
    }
    int32_t pool_at = 0;
    for (size_t i = 0; i < lights.size(); ++i) {
        float* row = &t.data[LightTable::kStride * i];
        int32_t* irow = &t.idata[LightTable::kIntStride * i];
        irow[3] = 2, irow[4] = 3;
        Spectrum L(0.f);
        if (const auto* a = std::get_if<AreaLight>(&lights[i]); a && !a->is_sphere()) {
            // A mesh: its triangles and CDF appended to the table's (offsets kept below 2²³, so
            // that floats hold them exactly; a light past that stays without a row).
            const size_t count = a->sampling_cdf().size() - 1;
            const size_t first = t.mesh_rows.size() / kMeshLightStride, cdf_at = t.mesh_cdf.size();
            if (count == 0 || first + count >= (size_t(1) << 23) || cdf_at + count + 1 >= (size_t(1) << 23)) continue;
            t.kind[i] = LightTable::kMesh;
            t.mesh_rows.insert(t.mesh_rows.end(), a->sampling_rows().begin(), a->sampling_rows().end());
            t.mesh_cdf.insert(t.mesh_cdf.end(), a->sampling_cdf().begin(), a->sampling_cdf().end());
            t.mesh_top = std::max(t.mesh_top, a->sampling_top());
            row[1] = float(first), row[2] = float(cdf_at), row[3] = float(count);
            row[4] = a->area();
            row[6] = a->two_sided() ? 1.f : 0.f;
            L = a->radiance();
        } else if (const auto* a = std::get_if<AreaLight>(&lights[i]); a && a->is_sphere()) {
            t.kind[i] = LightTable::kSphere;
            for (int c = 0; c < 3; ++c) row[1 + c] = a->center()[c];
            row[4] = a->radius();
            row[5] = a->flipped() ? 1.f : 0.f;
            row[6] = a->two_sided() ? 1.f : 0.f;
            L = a->radiance();
        } else if (const auto* pt = std::get_if<PointLight>(&lights[i])) {
            t.kind[i] = LightTable::kPoint;
            for (int c = 0; c < 3; ++c) row[1 + c] = pt->position()[c];
            L = pt->intensity();
        } else if (const auto* sp = std::get_if<SpotLight>(&lights[i])) {
            t.kind[i] = LightTable::kSpot;
            for (int c = 0; c < 3; ++c) row[1 + c] = sp->position()[c], row[4 + c] = sp->axis()[c];
            row[10] = sp->cos_cutoff(), row[11] = sp->cutoff(), row[12] = sp->beam();
            L = sp->intensity();
        } else if (const auto* dl = std::get_if<DirectionalLight>(&lights[i])) {
            t.kind[i] = LightTable::kDirectional;
            for (int c = 0; c < 3; ++c) row[1 + c] = dl->direction()[c];
            L = dl->irradiance();
        } else if (const auto* k = std::get_if<ConstantLight>(&lights[i])) {
            t.kind[i] = LightTable::kConstant;
            L = k->radiance();
        } else if (const auto* e = std::get_if<EnvmapLight>(&lights[i])) {
            t.kind[i] = LightTable::kEnvmap;
            for (int c = 0; c < 3; ++c)
                for (int k2 = 0; k2 < 3; ++k2) row[1 + 3 * c + k2] = e->rotation()[c][k2];
            irow[0] = pool_at + e->layout().marginal;
            irow[1] = pool_at + e->layout().conditional;
            irow[2] = pool_at + e->texel_offset();
            irow[3] = e->width(), irow[4] = e->height();
            if (maps.size() > 1) pool_at += int32_t(e->data()->size());
            t.sole_envmap = maps.size() == 1 ? int32_t(i) : -1;
            row[0] = float(t.kind[i]);
            t.infinite.push_back(int32_t(i));
            t.infinite_pmf.push_back(i < pmf.size() ? pmf[i] : 0.f);
            t.any = true;
            continue;
        } else {
            continue;
        }
        row[0] = float(t.kind[i]);
        for (int c = 0; c < 3; ++c) row[7 + c] = L[c];
        if (t.kind[i] == LightTable::kConstant) {
            t.infinite.push_back(int32_t(i));
            t.infinite_pmf.push_back(i < pmf.size() ? pmf[i] : 0.f);
        }
        t.any = true;
    }
    return t;
}
template LightTable make_light_table<Light>(const std::vector<Light>&, const std::vector<float>&);
}  // namespace pellucid
