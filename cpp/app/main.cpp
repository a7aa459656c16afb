// pellucid-render: the standalone renderer (no Python needed).
// Usage: pellucid-render [render] SCENE -o OUT [-o OUT2 ...] [--spp N] [--seed S] [--threads T]
//                        [--sampler independent|sobol] [--time-budget SECONDS] [--aov albedo|normal|depth]
//                        [--lenient] [--quiet]
// The same flags as `python -m pellucid render`; the same scene and seed give the same image.
// SPDX-License-Identifier: Apache-2.0
#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "pellucid/api.h"
#include "pellucid/util/error.h"

namespace {
std::atomic<bool> g_cancel{false};
extern "C" void on_sigint(int) { g_cancel = true; }

const char* kUsage =
    "usage: pellucid-render [render] SCENE -o OUT [-o OUT ...] [--spp N] [--seed S] [--threads T]\n"
    "                       [--sampler independent|sobol] [--time-budget SECONDS] [--aov albedo|normal|depth]\n"
    "                       [--lenient] [--quiet]\n"
    "Renders SCENE (.json or Mitsuba 3 .xml) and writes each OUT (.exr keeps HDR values; .png/.jpg are\n"
    "tone-mapped sRGB). --lenient: unsupported Mitsuba XML elements are warnings (skipped), not errors.\n"
    "--aov renders that AOV of the first hit instead of the scene's integrator (signed normals and depth\n"
    "need .exr to keep their values). --sampler overrides the scene's sampler type (sobol: Owen-scrambled\n"
    "Sobol, lower error at equal spp).\n";

[[noreturn]] void usage_error(const std::string& msg) {
    std::fprintf(stderr, "pellucid-render: error: %s\n%s", msg.c_str(), kUsage);
    std::exit(2);
}

long long parse_int(const std::string& flag, const std::string& v) {
    char* end = nullptr;
    long long x = std::strtoll(v.c_str(), &end, 10);
    if (v.empty() || *end) usage_error(flag + ": expected an integer, got '" + v + "'");
    return x;
}
}  // namespace

int main(int argc, char** argv) {
    std::vector<std::string> args(argv + 1, argv + argc);
    std::string scene_path;
    std::vector<std::string> outputs;
    pellucid::RenderOptions opts;
    opts.progress = true;
    bool quiet = false, lenient = false;
    std::string aov;
    for (size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        auto value = [&](const char* flag) -> std::string {
            if (i + 1 >= args.size()) usage_error(std::string(flag) + " needs a value");
            return args[++i];
        };
        if (a == "-h" || a == "--help") {
            std::printf("%s", kUsage);
            return 0;
        } else if (a == "--version") {
            std::printf("pellucid %s\n", pellucid::version());
            return 0;
        } else if (a == "-o" || a == "--output") {
            outputs.push_back(value("-o"));
        } else if (a == "--spp") {
            long long v = parse_int("--spp", value("--spp"));
            if (v < 1 || v > (1 << 24)) usage_error("--spp: value " + std::to_string(v) + " must be in [1, 16777216]");
            opts.spp = int(v);
        } else if (a == "--seed") {
            long long v = parse_int("--seed", value("--seed"));
            if (v < 0) usage_error("--seed: value must be >= 0");
            opts.seed = v;
        } else if (a == "--threads") {
            long long v = parse_int("--threads", value("--threads"));
            if (v < 0 || v > 4096) usage_error("--threads: value must be in [0, 4096]");
            opts.threads = int(v);
        } else if (a == "--sampler") {
            opts.sampler = value("--sampler");
            if (opts.sampler != "independent" && opts.sampler != "sobol")
                usage_error("--sampler: unknown sampler '" + opts.sampler + "' (known: independent, sobol)");
        } else if (a == "--time-budget") {
            std::string v = value("--time-budget");
            char* end = nullptr;
            opts.time_budget = std::strtod(v.c_str(), &end);
            if (v.empty() || *end || !(opts.time_budget > 0)) usage_error("--time-budget: expected seconds > 0");
        } else if (a == "--aov") {
            aov = value("--aov");
            if (aov != "albedo" && aov != "normal" && aov != "depth")
                usage_error("--aov: unknown aov '" + aov + "' (known: albedo, depth, normal)");
        } else if (a == "--lenient") {
            lenient = true;
        } else if (a == "--quiet" || a == "-q") {
            quiet = true;
        } else if (a == "render" && scene_path.empty() && i == 0) {
            continue;
        } else if (!a.empty() && a[0] == '-') {
            usage_error("unknown option '" + a + "'");
        } else if (scene_path.empty()) {
            scene_path = a;
        } else {
            usage_error("unexpected argument '" + a + "'");
        }
    }
    if (scene_path.empty()) usage_error("no scene file given");
    if (outputs.empty()) usage_error("no output given (-o OUT.exr)");
    opts.progress = !quiet;
    opts.cancel = &g_cancel;
    std::signal(SIGINT, on_sigint);
    try {
        auto scene = pellucid::load_file(scene_path, lenient);
        pellucid::RenderResult r = aov.empty() ? pellucid::render(*scene, opts) : pellucid::render_aov(*scene, aov, opts);
        for (const auto& out : outputs) {
            pellucid::write_image(out, r.image);
            if (!quiet) std::fprintf(stderr, "wrote %s\n", out.c_str());
        }
        if (r.stats.invalid_samples)
            std::fprintf(stderr, "pellucid-render: warning: %llu NaN/Inf/negative samples were discarded\n",
                         (unsigned long long)r.stats.invalid_samples);
        if (!quiet)
            std::fprintf(stderr, "%d spp, %.3f s, %.3f M samples/s\n", r.stats.spp, r.stats.seconds,
                         double(r.stats.samples) / r.stats.seconds * 1e-6);
        if (r.stats.cancelled) {
            std::fprintf(stderr, "pellucid-render: interrupted; the image holds the samples finished so far\n");
            return 130;
        }
    } catch (const pellucid::Error& e) {
        std::fprintf(stderr, "pellucid-render: error: %s\n", e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "pellucid-render: internal error: %s\n", e.what());
        return 3;
    }
    return 0;
}
