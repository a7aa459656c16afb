// "Did you mean ...?" for names a user mistyped: unknown types and unknown keys in scene files.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <string>
#include <vector>

namespace pellucid {

/// Edit distance between a and b, ignoring case: insertions, deletions, substitutions and swaps of
/// two adjacent characters each count 1 (optimal string alignment distance).
size_t edit_distance(const std::string& a, const std::string& b);

/// The candidates nearest to `name`, nearest first (ties in the candidates' order), keeping only
/// those within max(1, name.size() / 3) edits, or that contain `name` or are contained in it once
/// case and '_' are ignored ("roughconductor" -> "rough_conductor"). Empty when none is that close.
/// At most `max_count` names.
std::vector<std::string> closest_names(const std::string& name, const std::vector<std::string>& candidates,
                                       size_t max_count = 2);

/// "did you mean 'a'?" or "did you mean 'a' or 'b'?" from closest_names; "" when nothing is close.
std::string did_you_mean(const std::string& name, const std::vector<std::string>& candidates);
}  // namespace pellucid
