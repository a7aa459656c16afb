// A float image, contiguous row-major (H, W, C); exposed to numpy without a copy.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <cstddef>
#include <vector>

namespace pellucid {
struct Image {
    int width = 0, height = 0, channels = 3;
    std::vector<float> data;

    Image() = default;
    Image(int w, int h, int c = 3) : width(w), height(h), channels(c), data(std::size_t(w) * h * c, 0.f) {}
    float* pixel(int x, int y) { return data.data() + (std::size_t(y) * width + x) * channels; }
    const float* pixel(int x, int y) const { return data.data() + (std::size_t(y) * width + x) * channels; }
};
}  // namespace pellucid
