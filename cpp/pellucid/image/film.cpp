// Film accumulation.
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/image/film.h"

namespace pellucid {

Film::Film(int width, int height) : m_width(width), m_height(height), m_pixels(size_t(width) * height) {}

Image Film::mean() const {
    Image img(m_width, m_height, 3);
    for (size_t i = 0; i < m_pixels.size(); ++i)
        for (int k = 0; k < 3; ++k) img.data[3 * i + k] = float(m_pixels[i].mean[k]);
    return img;
}

Image Film::variance() const {
    Image img(m_width, m_height, 3);
    for (size_t i = 0; i < m_pixels.size(); ++i) {
        const Pixel& p = m_pixels[i];
        for (int k = 0; k < 3; ++k)
            img.data[3 * i + k] = p.n > 1 ? float(p.m2[k] / double(p.n - 1) / double(p.n)) : 0.f;
    }
    return img;
}

double Film::mean_relative_variance() const {
    double sum = 0.0;
    for (const Pixel& p : m_pixels) {
        if (p.n < 2) return 1e30;
        double m = 0.2126 * p.mean[0] + 0.7152 * p.mean[1] + 0.0722 * p.mean[2];
        double v = (0.2126 * p.m2[0] + 0.7152 * p.m2[1] + 0.0722 * p.m2[2]) / double(p.n - 1) / double(p.n);
        sum += v / (m * m + 1e-4);
    }
    return sum / double(m_pixels.size());
}
}  // namespace pellucid
