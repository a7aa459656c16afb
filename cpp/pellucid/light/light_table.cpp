// The packet lights' table (light_table.h).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/light/light_table.h"

#include "pellucid/light/light.h"

namespace pellucid {

template <class LightT>
LightTable make_light_table(const std::vector<LightT>& lights) {
    LightTable t;
    t.data.assign(LightTable::kStride * lights.size(), 0.f);
    t.kind.assign(lights.size(), LightTable::kNone);
    for (size_t i = 0; i < lights.size(); ++i) {
        float* row = &t.data[LightTable::kStride * i];
        Spectrum L(0.f);
        if (const auto* a = std::get_if<AreaLight>(&lights[i]); a && a->is_sphere()) {
            t.kind[i] = LightTable::kSphere;
            for (int c = 0; c < 3; ++c) row[1 + c] = a->center()[c];
            row[4] = a->radius();
            row[5] = a->flipped() ? 1.f : 0.f;
            row[6] = a->two_sided() ? 1.f : 0.f;
            L = a->radiance();
        } else if (const auto* k = std::get_if<ConstantLight>(&lights[i])) {
            t.kind[i] = LightTable::kConstant;
            L = k->radiance();
        } else {
            continue;
        }
        row[0] = float(t.kind[i]);
        for (int c = 0; c < 3; ++c) row[7 + c] = L[c];
        t.any = true;
    }
    return t;
}
template LightTable make_light_table<Light>(const std::vector<Light>&);
}  // namespace pellucid
