// A scratch directory per test: ctest runs tests in parallel processes, so a directory shared by
// several tests (and removed by one of them) is a race. The name carries the test's name.
// SPDX-License-Identifier: Apache-2.0
#pragma once
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace pellucid::test {

class TempDir {
public:
    /// <system temp>/<prefix><test name>, emptied on creation and removed on destruction.
    explicit TempDir(const std::string& prefix) {
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        m_path = std::filesystem::temp_directory_path() / (prefix + info->name());
        std::filesystem::remove_all(m_path);
        std::filesystem::create_directories(m_path);
    }
    ~TempDir() { std::filesystem::remove_all(m_path); }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
    std::string file(const std::string& name) const { return (m_path / name).string(); }
    std::string dir() const { return m_path.string(); }
    const std::filesystem::path& path() const { return m_path; }

private:
    std::filesystem::path m_path;
};
}  // namespace pellucid::test
