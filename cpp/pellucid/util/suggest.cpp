// Nearest-name suggestions for error messages (util/suggest.h).
// SPDX-License-Identifier: Apache-2.0
#include "pellucid/util/suggest.h"

#include <algorithm>
#include <cctype>

namespace pellucid {
namespace {
std::string lower(const std::string& s) {
    std::string out(s);
    for (char& c : out) c = char(std::tolower(static_cast<unsigned char>(c)));
    return out;
}
/// Lower case without '_', '-' and spaces: "Rough_Conductor" and "roughconductor" agree.
std::string squeezed(const std::string& s) {
    std::string out;
    for (char c : s)
        if (c != '_' && c != '-' && c != ' ') out += char(std::tolower(static_cast<unsigned char>(c)));
    return out;
}
}  // namespace

size_t edit_distance(const std::string& a_in, const std::string& b_in) {
    const std::string a = lower(a_in), b = lower(b_in);
    const size_t n = a.size(), m = b.size();
    // Three rows of the dynamic-programming table: i-2, i-1 and i.
    std::vector<size_t> prev2(m + 1), prev(m + 1), cur(m + 1);
    for (size_t j = 0; j <= m; ++j) prev[j] = j;
    for (size_t i = 1; i <= n; ++i) {
        cur[0] = i;
        for (size_t j = 1; j <= m; ++j) {
            size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
            cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + cost});
            if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1])
                cur[j] = std::min(cur[j], prev2[j - 2] + 1);
        }
        std::swap(prev2, prev);
        std::swap(prev, cur);
    }
    return prev[m];
}

std::vector<std::string> closest_names(const std::string& name, const std::vector<std::string>& candidates,
                                       size_t max_count) {
    const size_t limit = std::max<size_t>(1, name.size() / 3);
    const std::string sq = squeezed(name);
    std::vector<std::pair<size_t, size_t>> scored;  // (distance, index in candidates)
    for (size_t i = 0; i < candidates.size(); ++i) {
        const std::string& c = candidates[i];
        if (c == name) continue;
        const std::string csq = squeezed(c);
        size_t d = edit_distance(name, c);
        if (!sq.empty() && sq.size() >= 3 && csq == sq) d = 0;  // differs only in case or separators
        else if (d > limit && sq.size() >= 4 && !csq.empty() &&
                 (csq.find(sq) != std::string::npos || sq.find(csq) != std::string::npos))
            d = limit;  // one name contains the other: "conductor" for "roughconductor"
        if (d <= limit) scored.emplace_back(d, i);
    }
    std::stable_sort(scored.begin(), scored.end(),
                     [](const auto& x, const auto& y) { return x.first < y.first; });
    std::vector<std::string> out;
    for (size_t k = 0; k < scored.size() && k < max_count; ++k) out.push_back(candidates[scored[k].second]);
    return out;
}

std::string did_you_mean(const std::string& name, const std::vector<std::string>& candidates) {
    std::vector<std::string> near = closest_names(name, candidates);
    if (near.empty()) return "";
    std::string s = "did you mean '" + near[0] + "'";
    for (size_t k = 1; k < near.size(); ++k) s += " or '" + near[k] + "'";
    return s + "?";
}
}  // namespace pellucid
