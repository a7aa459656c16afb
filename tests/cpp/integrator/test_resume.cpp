// Interrupts and resume: cancellation stops a render within a pass and leaves a film of whole
// passes; film state files round-trip bit for bit and refuse corrupt input; a render continued from
// a state (after finishing or after a cancellation) is bit-identical to an uninterrupted one.
// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

#include "pellucid/api.h"
#include "pellucid/image/film.h"
#include "pellucid/integrator/render_loop.h"
#include "support/scene_util.h"

using namespace pellucid;
using pellucid::test::scene_from;

namespace {
/// Spheres, a rectangle floor and an area light; `film_extra` goes into "film".
std::string scene_json(const std::string& film_extra, const std::string& sampler = "independent", int w = 40,
                       int h = 30) {
    return std::string(R"({"camera": {"type": "perspective", "fov": 45,
        "to_world": [{"look_at": {"origin": [0, 1.5, 4], "target": [0, 0, 0], "up": [0, 1, 0]}}]},
        "film": {"width": )") + std::to_string(w) + R"(, "height": )" + std::to_string(h) + film_extra +
           R"(}, "sampler": {"type": ")" + sampler + R"(", "sample_count": 4, "seed": 3},
        "integrator": {"type": "path", "max_depth": 4},
        "materials": {"white": {"type": "lambertian", "reflectance": 0.7},
                      "red": {"type": "lambertian", "reflectance": [0.8, 0.1, 0.1]}},
        "shapes": [{"type": "sphere", "radius": 0.8, "material": "red"},
                   {"type": "rectangle", "material": "white",
                    "to_world": [{"scale": 3}, {"rotate": {"axis": [1, 0, 0], "angle": -90}}, {"translate": [0, -0.8, 0]}]},
                   {"type": "rectangle", "to_world": [{"scale": 0.4}, {"rotate": {"axis": [1, 0, 0], "angle": 90}}, {"translate": [0.5, 2.5, 0.5]}],
                    "emitter": {"type": "area", "radiance": 10}}]})";
}
const char* kSplat = R"(, "filter": {"type": "gaussian", "stddev": 0.5}, "reconstruction": "splatting")";
const char* kTent = R"(, "filter": {"type": "tent"})";

bool same_bits(const Image& a, const Image& b) {
    return a.width == b.width && a.height == b.height && a.data.size() == b.data.size() &&
           std::memcmp(a.data.data(), b.data.data(), a.data.size() * sizeof(float)) == 0;
}

std::string temp_path(const std::string& name) {
    return (std::filesystem::temp_directory_path() / ("pellucid_test_resume_" + name)).string();
}

std::string read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void write_bytes(const std::string& path, const std::string& data) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(data.data(), std::streamsize(data.size()));
}

std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

RenderResult render_spp(const Scene& s, int spp, std::shared_ptr<const FilmState> resume = nullptr, int threads = 2) {
    RenderOptions o;
    o.spp = spp;
    o.threads = threads;
    o.resume = std::move(resume);
    return render(s, o);
}

/// A deterministic estimator for render_loop tests: the sample's first random number in R, the
/// pixel position in G and B. `delay` sleeps per tile, to make passes slow.
TileFn test_tiles(const Scene& scene, std::chrono::milliseconds delay, std::atomic<int>* tiles = nullptr,
                  std::function<void(int)> on_tile = nullptr) {
    return [&scene, delay, tiles, on_tile](const TileJob& job, Film& film) {
        if (delay.count() > 0) std::this_thread::sleep_for(delay);
        if (tiles) {
            const int k = ++*tiles;
            if (on_tile) on_tile(k);
        }
        return render_tile(scene, job, film, SamplerType::Independent, [](const RayDifferential& r, Sampler& u) {
            return Spectrum(u.get_1d(), std::fabs(r.d.x), std::fabs(r.d.y));
        });
    };
}
}  // namespace

class ResumeBitIdentical : public ::testing::TestWithParam<std::tuple<const char*, const char*>> {};

// Continuing a finished render to more samples gives the uninterrupted render's image, bit for bit,
// for both reconstructions and both samplers, and for a state written to a file and read back.
TEST_P(ResumeBitIdentical, FinishedThenContinued) {
    const auto [film, sampler] = GetParam();
    auto scene = scene_from(scene_json(film, sampler));
    const RenderResult full = render_spp(*scene, 12);
    // Any split for filter sampling; even ones (pass boundaries) for splatting.
    for (int split : {2, 6, 10}) {
        const RenderResult first = render_spp(*scene, split);
        const RenderResult resumed = render_spp(*scene, 12, first.state);
        EXPECT_EQ(resumed.stats.spp, 12);
        EXPECT_TRUE(same_bits(full.image, resumed.image)) << "split at " << split;
        EXPECT_TRUE(same_bits(full.variance, resumed.variance)) << "split at " << split;
    }
    if (film != kSplat) EXPECT_TRUE(same_bits(full.image, render_spp(*scene, 12, render_spp(*scene, 5).state).image));
    const RenderResult part = render_spp(*scene, 6);
    ASSERT_EQ(part.state->spp, 6);
    // Through a file, and with another thread count.
    const std::string path = temp_path(std::string("finished_") + sampler + (film == kSplat ? "_splat" : "_tent"));
    save_film_state(path, *part.state);
    const RenderResult from_file = render_spp(*scene, 12, load_film_state(path), 1);
    EXPECT_TRUE(same_bits(full.image, from_file.image));
    std::filesystem::remove(path);
    // A state at the requested spp renders nothing more and returns the same image.
    const RenderResult same = render_spp(*scene, 6, part.state);
    EXPECT_TRUE(same_bits(part.image, same.image));
}

// Cancelled at whatever point a timer hits (during a render far too long to finish), then continued
// a few samples past that point: bit-identical to an uninterrupted render of that length.
// The timer fires 0.25 s in, but never before a splatting pass's samples (splat_pass_spp: 16 spp at
// this size) have been taken: a first pass is at most that (1 spp with filter sampling), so at least
// one pass is whole however slow the build. (A sanitizer build on a loaded machine took longer than
// 0.25 s for the first pass, which a cancellation midway discards.)
TEST_P(ResumeBitIdentical, CancelledThenContinued) {
    const auto [film, sampler] = GetParam();
    const int w = 48, h = 36;
    auto scene = scene_from(scene_json(film, sampler, w, h));
    std::atomic<bool> cancel{false};
    RenderProgress progress;
    RenderOptions o;
    o.spp = 1 << 24;
    o.cancel = &cancel;
    o.progress_out = &progress;
    std::thread timer([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(250));
        const uint64_t first_pass = uint64_t(splat_pass_spp(w, h)) * w * h;
        while (progress.samples.load() < first_pass) std::this_thread::sleep_for(std::chrono::milliseconds(1));
        cancel = true;
    });
    const RenderResult part = render(*scene, o);
    timer.join();
    ASSERT_TRUE(part.stats.cancelled);
    ASSERT_GT(part.stats.spp, 0);
    if (film == kSplat) EXPECT_EQ(part.stats.spp % 2, 0);
    const int spp = part.stats.spp + 7;
    const RenderResult full = render_spp(*scene, spp);
    const RenderResult resumed = render_spp(*scene, spp, part.state);
    EXPECT_TRUE(same_bits(full.image, resumed.image)) << "cancelled at " << part.stats.spp << " spp";
    EXPECT_TRUE(same_bits(full.variance, resumed.variance));
}

INSTANTIATE_TEST_SUITE_P(Films, ResumeBitIdentical,
                         ::testing::Combine(::testing::Values(kTent, kSplat), ::testing::Values("independent", "sobol")));

TEST(Resume, CornellBox) {
    auto scene = load_file(std::string(PELLUCID_SOURCE_DIR) + "/scenes/cornell_box.json");
    const RenderResult full = render_spp(*scene, 5);
    const RenderResult part = render_spp(*scene, 2);
    EXPECT_TRUE(same_bits(full.image, render_spp(*scene, 5, part.state).image));
}

// A cancellation during a short pass finishes that pass; during a long pass (over 0.25 s) it skips
// the tiles not started and returns the film of the passes before. Either way every pixel has the
// reported spp, and the image is that of an uncancelled render at that spp.
TEST(RenderLoopCancel, ShortPassIsFinished) {
    auto scene = scene_from(scene_json(kTent, "independent", 64, 64));  // 16 tiles
    std::atomic<bool> cancel{false};
    std::atomic<int> tiles{0};
    RenderOptions o;
    o.spp = 1000;
    o.threads = 1;
    o.cancel = &cancel;
    // 16 tiles per pass; cancel in the middle of the third pass (tiles 33..48).
    RenderResult r = render_loop(*scene, o, test_tiles(*scene, std::chrono::milliseconds(0), &tiles, [&](int k) {
        if (k == 40) cancel = true;
    }));
    EXPECT_TRUE(r.stats.cancelled);
    EXPECT_EQ(tiles.load() % 16, 0) << "a pass was left unfinished";
    ASSERT_GE(r.stats.spp, 3);
    RenderOptions plain;
    plain.spp = r.stats.spp;
    EXPECT_TRUE(same_bits(r.image, render_loop(*scene, plain, test_tiles(*scene, std::chrono::milliseconds(0))).image));
}

TEST(RenderLoopCancel, LongPassIsRolledBack) {
    auto scene = scene_from(scene_json(kTent, "independent", 64, 64));  // 16 tiles
    std::atomic<bool> cancel{false};
    std::atomic<int> tiles{0};
    RenderOptions o;
    o.spp = 1000;
    o.threads = 1;
    o.cancel = &cancel;
    // 16 tiles × 25 ms = 0.4 s per 1-spp pass: every pass keeps a copy. Cancel after tile 40, in
    // the third pass: the render returns the 2 complete passes.
    auto t0 = std::chrono::steady_clock::now();
    RenderResult r = render_loop(*scene, o, test_tiles(*scene, std::chrono::milliseconds(25), &tiles, [&](int k) {
        if (k == 40) cancel = true;
    }));
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_TRUE(r.stats.cancelled);
    EXPECT_EQ(tiles.load(), 40) << "tiles ran after the cancellation";
    EXPECT_EQ(r.stats.spp, 2);
    EXPECT_LT(secs, 1.5);
    RenderOptions plain;
    plain.spp = 2;
    const TileFn fast = test_tiles(*scene, std::chrono::milliseconds(0));
    EXPECT_TRUE(same_bits(r.image, render_loop(*scene, plain, fast).image));
    EXPECT_TRUE(same_bits(r.variance, render_loop(*scene, plain, fast).variance));
    // And it resumes to the uninterrupted render.
    plain.spp = 5;
    const RenderResult full = render_loop(*scene, plain, fast);
    plain.resume = r.state;
    EXPECT_TRUE(same_bits(full.image, render_loop(*scene, plain, fast).image));
}

// At any spp, a real render stops within a second of the cancellation: a large spp with fast
// passes, and a film large enough that one spp takes longer than the cancellation latency.
TEST(RenderLoopCancel, StopsWithinASecond) {
    for (int size : {64, 1024}) {
        auto scene = scene_from(scene_json(kTent, "independent", size, size));
        std::atomic<bool> cancel{false};
        RenderOptions o;
        o.spp = 1 << 24;
        o.cancel = &cancel;
        std::chrono::steady_clock::time_point t_cancel;
        std::thread timer([&] {
            std::this_thread::sleep_for(std::chrono::milliseconds(size == 64 ? 300 : 1500));
            t_cancel = std::chrono::steady_clock::now();
            cancel = true;
        });
        RenderResult r = render(*scene, o);
        const auto t_end = std::chrono::steady_clock::now();
        timer.join();
        const double latency = std::chrono::duration<double>(t_end - t_cancel).count();
        EXPECT_TRUE(r.stats.cancelled);
        EXPECT_LT(latency, 1.0) << size << "² film";
        EXPECT_EQ(r.stats.samples, uint64_t(size) * size * uint64_t(r.stats.spp));
        std::printf("  %d² film: stopped %.3f s after the cancellation at %d spp\n", size, latency, r.stats.spp);
    }
}

TEST(FilmStateFile, RoundTripsBitForBit) {
    for (const char* film : {kTent, kSplat}) {
        auto scene = scene_from(scene_json(film));
        const RenderResult r = render_spp(*scene, 3);
        const std::string a = temp_path("roundtrip_a"), b = temp_path("roundtrip_b");
        save_film_state(a, *r.state);
        auto st = load_film_state(a);
        EXPECT_EQ(st->spp, 3);
        EXPECT_EQ(st->seed, 3u);
        EXPECT_EQ(st->sampler, "independent");
        EXPECT_EQ(st->integrator, r.state->integrator);
        EXPECT_EQ(st->film.splats(), film == kSplat);
        EXPECT_TRUE(same_bits(st->film.mean(), r.image));
        EXPECT_TRUE(same_bits(st->film.variance(), r.variance));
        save_film_state(b, *st);
        EXPECT_EQ(read_bytes(a), read_bytes(b));
        EXPECT_FALSE(std::filesystem::exists(a + ".part"));
        std::filesystem::remove(a);
        std::filesystem::remove(b);
    }
}

TEST(FilmStateFile, CorruptFilesAreRefused) {
    auto scene = scene_from(scene_json(kTent));
    const std::string path = temp_path("corrupt");
    save_film_state(path, *render_spp(*scene, 2).state);
    const std::string good = read_bytes(path);

    std::string flipped = good;
    flipped[good.size() / 2] ^= 0x10;
    write_bytes(path, flipped);
    EXPECT_NE(error_of([&] { load_film_state(path); }).find(path + ": checksum mismatch"), std::string::npos);

    write_bytes(path, good.substr(0, good.size() - 100));
    EXPECT_NE(error_of([&] { load_film_state(path); }).find("truncated film state file"), std::string::npos);

    write_bytes(path, "P3\n1 1\n255\n0 0 0\n");
    EXPECT_NE(error_of([&] { load_film_state(path); }).find("not a pellucid film state file"), std::string::npos);

    std::string version = good;
    version[8] = 7;
    write_bytes(path, version);
    EXPECT_NE(error_of([&] { load_film_state(path); }).find("film state version 7 is not supported"), std::string::npos);

    std::filesystem::remove(path);
    EXPECT_NE(error_of([&] { load_film_state(path); }).find("cannot open film state file"), std::string::npos);
}

TEST(Resume, MismatchesAreErrors) {
    auto scene = scene_from(scene_json(kTent));
    auto st = render_spp(*scene, 4).state;
    EXPECT_NE(error_of([&] { render_spp(*scene, 2, st); }).find("spp: value 2 is below the 4 spp"), std::string::npos);
    EXPECT_NE(error_of([&] { render_spp(*scene_from(scene_json(kTent, "independent", 41, 30)), 8, st); })
                  .find("resume: the film state is 40x30 pixels, the scene 41x30"),
              std::string::npos);
    EXPECT_NE(error_of([&] { render_spp(*scene_from(scene_json(kSplat)), 8, st); }).find("resume: the film state samples the filter"),
              std::string::npos);
    EXPECT_NE(error_of([&] { render_spp(*scene_from(scene_json("")), 8, st); }).find("filter is TentFilter"),
              std::string::npos);
    EXPECT_NE(error_of([&] { render_spp(*scene_from(scene_json(kTent, "sobol")), 8, st); })
                  .find("used the independent sampler, this render the sobol sampler"),
              std::string::npos);
    RenderOptions o;
    o.spp = 8;
    o.seed = 9;
    o.resume = st;
    EXPECT_NE(error_of([&] { render(*scene, o); }).find("used seed 3, this render asks for seed 9"), std::string::npos);
    EXPECT_NE(error_of([&] { render_aov(*scene, "normal", o); }).find("resume: the film state was rendered by PathIntegrator"),
              std::string::npos);
}

// A splatting render with variance off: the same image bit for bit, no variance image; its state
// resumes (through a file too) to the uninterrupted render's image, without variance; asking for
// variance, or a target_rel_error, from that state is an error naming what is missing; a version 1
// state file (no variance byte) is still read.
TEST(Resume, WithoutVariance) {
    auto scene = scene_from(scene_json(kSplat));
    RenderOptions o;
    o.spp = 8;
    o.threads = 2;
    const RenderResult with = render(*scene, o);
    o.variance = false;
    const RenderResult full = render(*scene, o);
    EXPECT_TRUE(same_bits(with.image, full.image));
    EXPECT_TRUE(full.variance.data.empty());
    EXPECT_FALSE(full.state->film.has_variance());
    o.spp = 4;
    const RenderResult part = render(*scene, o);
    const std::string path = temp_path("no_variance");
    save_film_state(path, *part.state);
    o.spp = 8;
    o.resume = load_film_state(path);
    EXPECT_FALSE(o.resume->film.has_variance());
    const RenderResult resumed = render(*scene, o);
    EXPECT_TRUE(same_bits(full.image, resumed.image));
    EXPECT_TRUE(resumed.variance.data.empty());
    o.variance = true;
    EXPECT_NE(error_of([&] { render(*scene, o); }).find("resume: the film state was rendered without variance"),
              std::string::npos);
    o.variance = false;
    o.target_rel_error = 0.1;
    EXPECT_NE(error_of([&] { render(*scene, o); }).find("stops at a target_rel_error, which needs it"), std::string::npos);
    // target_rel_error keeps variance even when variance is off.
    RenderOptions t;
    t.spp = 4, t.variance = false, t.target_rel_error = 1e-9;
    EXPECT_FALSE(render(*scene, t).variance.data.empty());
    // A version 1 file: the version-2 file of a film with variance, less its variance byte.
    save_film_state(path, *with.state);
    std::string v1 = read_bytes(path);
    ASSERT_EQ(v1[8], 2);
    v1[8] = 1;
    v1.erase(8 + 4 + 8 + 1, 1);  // magic, version, width and height, reconstruction: the variance byte
    // The checksum (FNV-1a of every byte before it), recomputed.
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i + 8 < v1.size(); ++i) h = (h ^ uint64_t(uint8_t(v1[i]))) * 1099511628211ull;
    std::memcpy(&v1[v1.size() - 8], &h, 8);
    write_bytes(path, v1);
    const auto old = load_film_state(path);
    std::filesystem::remove(path);
    EXPECT_TRUE(old->film.has_variance());
    EXPECT_TRUE(same_bits(old->film.mean(), with.image));
    EXPECT_TRUE(same_bits(old->film.variance(), with.variance));
}

// Dropped samples are counted across a resume and the state keeps their count.
TEST(Resume, InvalidSampleCountCarriesOver) {
    auto scene = scene_from(scene_json(kTent, "independent", 32, 32));
    RenderOptions o;
    o.spp = 4;
    auto nan_tiles = [&](const TileJob& job, Film& film) {
        return render_tile(*scene, job, film, SamplerType::Independent, [](const RayDifferential&, Sampler& u) {
            return u.get_1d() < 0.25f ? Spectrum(std::nanf("")) : Spectrum(1.f);
        });
    };
    const RenderResult full = render_loop(*scene, o, nan_tiles);
    o.spp = 2;
    const RenderResult part = render_loop(*scene, o, nan_tiles);
    EXPECT_GT(part.stats.invalid_samples, 0u);
    EXPECT_EQ(part.state->invalid_samples, part.stats.invalid_samples);
    o.spp = 4;
    o.resume = part.state;
    const RenderResult resumed = render_loop(*scene, o, nan_tiles);
    EXPECT_GT(full.stats.invalid_samples, part.stats.invalid_samples);
    EXPECT_EQ(resumed.stats.invalid_samples, full.stats.invalid_samples);
}
