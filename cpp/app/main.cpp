// pellucid-render: the standalone renderer (no Python needed).
// Usage: pellucid-render [render] SCENE -o OUT [-o OUT2 ...] [--spp N] [--seed S] [--threads T]
//                        [--sampler independent|sobol] [--aov albedo|normal|depth] [--aovs LIST]
//                        [--time-budget SECONDS]
//                        [-D NAME=VALUE ...] [--resume STATE] [--state STATE] [--lenient] [--quiet]
// The same flags, help and error format as `python -m pellucid render`; the same scene and seed
// give the same image. Arguments are parsed with CLI11 (only here).
// SPDX-License-Identifier: Apache-2.0
#include <signal.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "pellucid/api.h"
#include "pellucid/integrator/aov.h"
#include "pellucid/util/error.h"
#include "pellucid/util/log.h"

namespace {
constexpr const char* kProg = "pellucid-render";
std::atomic<bool> g_cancel{false};
volatile sig_atomic_t g_signal = 0;

// SIGINT/SIGTERM: ask the render to stop (it returns the complete passes, which are written). The
// handler is reset after the first signal, so a second one ends the process at once.
extern "C" void on_signal(int sig) {
    g_signal = sig;
    g_cancel.store(true);
}

void install_signal_handlers() {
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND;
    sigaction(SIGINT, &sa, nullptr);
    sigaction(SIGTERM, &sa, nullptr);
}

/// Word-wrap `text` to `width` columns, every line after the first indented by `indent`.
std::string wrap(const std::string& text, size_t first_col, size_t indent, size_t width = 79) {
    std::string out, word;
    size_t col = first_col;
    auto flush = [&] {
        if (word.empty()) return;
        if (col > indent && col + 1 + word.size() > width) {
            out += "\n" + std::string(indent, ' ');
            col = indent;
        } else if (col > first_col || (col > indent && !out.empty())) {
            out += ' ';
            ++col;
        }
        out += word;
        col += word.size();
        word.clear();
    };
    for (char c : text) {
        if (c == ' ') flush();
        else word += c;
    }
    flush();
    return out;
}

/// Help and errors in the layout of Python's argparse, so that both command lines read alike.
class ArgparseFormatter : public CLI::Formatter {
public:
    static std::string usage(const CLI::App* app) {
        std::vector<std::string> parts = {"[-h]"};
        std::vector<std::string> positionals;
        for (const CLI::Option* o : app->get_options()) {
            if (o->get_name() == "--help" || o->get_name() == "--version") continue;
            if (o->get_positional()) {
                positionals.push_back(o->get_name());
                continue;
            }
            std::string s = first_name(o);
            if (!o->get_type_name().empty()) s += " " + o->get_type_name();
            parts.push_back(o->get_required() ? s : "[" + s + "]");
        }
        parts.insert(parts.end(), positionals.begin(), positionals.end());
        const std::string head = std::string("usage: ") + kProg + " ";
        std::string line = head, out;
        for (const std::string& p : parts) {
            if (line.size() > head.size() && line.size() + p.size() + 1 > 79) {
                out += line + "\n";
                line = std::string(head.size(), ' ');
            }
            if (line.size() > head.size()) line += " ";
            line += p;
        }
        return out + line + "\n";
    }

    std::string make_help(const CLI::App* app, std::string, CLI::AppFormatMode) const override {
        std::string out = usage(app) + "\n" + app->get_description() + "\n\npositional arguments:\n";
        for (const CLI::Option* o : app->get_options())
            if (o->get_positional()) out += entry(o->get_name(), o->get_description());
        out += "\noptions:\n";
        for (const CLI::Option* o : app->get_options()) {
            if (o->get_positional()) continue;
            std::string names;
            const std::string meta = o->get_type_name().empty() ? "" : " " + o->get_type_name();
            for (const std::string& s : o->get_snames()) names += (names.empty() ? "-" : ", -") + s + meta;
            for (const std::string& l : o->get_lnames()) names += (names.empty() ? "--" : ", --") + l + meta;
            out += entry(names, o->get_description());
        }
        return out;
    }

private:
    static std::string first_name(const CLI::Option* o) {
        if (!o->get_snames().empty()) return "-" + o->get_snames().front();
        return "--" + o->get_lnames().front();
    }
    static std::string entry(const std::string& names, const std::string& desc) {
        std::string out = "  " + names;
        if (out.size() + 2 > 24) out += "\n" + std::string(24, ' ');
        else out += std::string(24 - out.size(), ' ');
        return out + wrap(desc, 24, 24) + "\n";
    }
};

/// A validator for numbers >= lo (or > lo), with argparse-like wording.
CLI::Validator number_above(double lo, bool inclusive) {
    return CLI::Validator(
        [lo, inclusive](std::string& v) -> std::string {
            char* end = nullptr;
            const double x = std::strtod(v.c_str(), &end);
            if (v.empty() || *end) return "invalid value '" + v + "'";
            if (inclusive ? x >= lo : x > lo) return "";
            return "value " + v + " must be " + (inclusive ? ">= " : "> ") + CLI::detail::to_string(lo);
        },
        "");
}

/// A validator for integers in [lo, hi], with argparse-like wording.
CLI::Validator integer_in(int64_t lo, int64_t hi) {
    return CLI::Validator(
        [lo, hi](std::string& v) -> std::string {
            char* end = nullptr;
            errno = 0;
            const long long x = std::strtoll(v.c_str(), &end, 10);
            if (v.empty() || *end) return "invalid int value '" + v + "'";
            if (errno == ERANGE || x < lo || x > hi) {
                if (hi == INT64_MAX) return "value " + v + " must be >= " + std::to_string(lo);
                return "value " + v + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
            }
            return "";
        },
        "");
}

/// A validator for a name from `known` (pellucid-render's wording before CLI11).
CLI::Validator one_of(const std::string& what, std::vector<std::string> known) {
    return CLI::Validator(
        [what, known](std::string& v) -> std::string {
            std::string list;
            for (const std::string& k : known) {
                if (k == v) return "";
                list += (list.empty() ? "" : ", ") + k;
            }
            return "unknown " + what + " '" + v + "' (known: " + list + ")";
        },
        "");
}

struct Args {
    std::string scene;
    std::vector<std::string> outputs, defines;
    std::string sampler, aov, aovs, resume, state;
    int spp = -1, threads = 0;
    int64_t seed = -1;
    double time_budget = 0.0;
    bool lenient = false, quiet = false;
};

/// Parse argv; returns -1 to go on, else the exit code (help, version, usage errors).
int parse(int argc, char** argv, Args& a) {
    // `pellucid-render render SCENE ...` is `pellucid-render SCENE ...`, as `python -m pellucid render`.
    std::vector<std::string> args(argv + 1, argv + argc);
    if (!args.empty() && args.front() == "render") args.erase(args.begin());
    std::reverse(args.begin(), args.end());  // CLI11 takes them last first

    CLI::App app("render a scene file", kProg);
    app.formatter(std::make_shared<ArgparseFormatter>());
    app.set_help_flag("-h,--help", "show this help message and exit");
    app.set_version_flag("--version", std::string("pellucid ") + pellucid::version(), "show the version and exit");
    app.add_option("scene", a.scene, "scene file (.json or Mitsuba 3 .xml)")->required();
    app.add_option("-o,--output", a.outputs,
                   "output image (.exr keeps HDR; .png/.jpg tone-mapped sRGB); repeatable; missing folders are created")
        ->required()
        ->type_name("OUTPUT")
        ->expected(1)
        ->take_all();
    app.add_option("--spp", a.spp, "samples per pixel (default: the scene's)")
        ->type_name("SPP")
        ->check(integer_in(1, 1 << 24));
    app.add_option("--seed", a.seed, "random seed (default: the scene's)")->type_name("SEED")->check(integer_in(0, INT64_MAX));
    app.add_option("--threads", a.threads, "worker threads (0 = all cores)")->type_name("THREADS")->check(integer_in(0, 4096));
    app.add_option("--sampler", a.sampler,
                   "override the scene's sampler type (sobol: Owen-scrambled Sobol, lower error at equal spp)")
        ->type_name("{independent,sobol}")
        ->check(one_of("sampler", {"independent", "sobol"}));
    app.add_option("--aov", a.aov,
                   "render this AOV of the first hit instead of the scene's integrator (as python -m pellucid render --aov)")
        ->type_name("{albedo,normal,depth}")
        ->check(one_of("aov", {"albedo", "depth", "normal"}));
    app.add_option("--aovs", a.aovs,
                   "also render these AOVs (comma-separated: " + pellucid::known_aovs() +
                       "), written as layers of every .exr OUTPUT (as python -m pellucid render --aovs)")
        ->type_name("AOVS")
        ->check(CLI::Validator(
            [](std::string& v) -> std::string {
                try {
                    pellucid::parse_aov_list(v, "aovs");
                } catch (const pellucid::Error& e) {
                    const std::string m = e.what();
                    return m.substr(m.find(": ") + 2);
                }
                return "";
            },
            ""));
    app.add_option("--time-budget", a.time_budget, "stop after about this many seconds")
        ->type_name("TIME_BUDGET")
        ->check(number_above(0.0, false));
    app.add_option("-D,--define", a.defines,
                   "set the Mitsuba XML parameter $NAME, overriding its <default> (repeatable)")
        ->type_name("NAME=VALUE")
        ->expected(1)
        ->take_all();
    app.add_option("--resume", a.resume,
                   "continue the render saved in this film state file up to --spp (same scene, seed and sampler)")
        ->type_name("STATE");
    app.add_option("--state", a.state,
                   "write the film state here when the render stops (default on interruption: first OUTPUT + .state)")
        ->type_name("STATE");
    app.add_flag("--lenient", a.lenient, "Mitsuba XML: unsupported elements are warnings (skipped), not errors");
    app.add_flag("-q,--quiet", a.quiet, "no progress bar or summary");
    app.failure_message([](const CLI::App* app, const CLI::Error& e) {
        std::string msg = e.what();
        // CLI11 says "--output is required"; argparse names every spelling of the missing argument.
        const std::string req = " is required";
        if (msg.size() > req.size() && msg.compare(msg.size() - req.size(), req.size(), req) == 0) {
            std::string names = msg.substr(0, msg.size() - req.size());
            for (const CLI::Option* o : app->get_options()) {
                if (o->get_name() != names) continue;
                std::string all;
                for (const std::string& s : o->get_snames()) all += (all.empty() ? "-" : "/-") + s;
                for (const std::string& l : o->get_lnames()) all += (all.empty() ? "--" : "/--") + l;
                if (!all.empty()) names = all;
            }
            msg = "the following arguments are required: " + names;
        }
        return ArgparseFormatter::usage(app) + kProg + ": error: " + msg + "\n";
    });
    try {
        app.parse(args);
    } catch (const CLI::ParseError& e) {
        const int rc = app.exit(e);
        return rc == 0 ? 0 : 2;
    }
    return -1;
}

/// Does the output path name an OpenEXR file (the format that holds AOV layers)?
bool is_exr(const std::string& path) {
    std::string ext = path.size() >= 4 ? path.substr(path.size() - 4) : "";
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return ext == ".exr";
}

/// -D NAME=VALUE pairs as a map; an entry without '=' or with an empty name is a usage error.
bool parse_defines(const std::vector<std::string>& defines, std::map<std::string, std::string>& out) {
    for (const std::string& d : defines) {
        const size_t eq = d.find('=');
        if (eq == std::string::npos || eq == 0) {
            std::fprintf(stderr, "%s: error: -D: expected NAME=VALUE, got '%s'\n", kProg, d.c_str());
            return false;
        }
        out[d.substr(0, eq)] = d.substr(eq + 1);
    }
    return true;
}
}  // namespace

int main(int argc, char** argv) {
    Args a;
    if (int rc = parse(argc, argv, a); rc >= 0) return rc;
    std::map<std::string, std::string> params;
    if (!parse_defines(a.defines, params)) return 2;
    pellucid::RenderOptions opts;
    opts.spp = a.spp;
    opts.seed = a.seed;
    opts.threads = a.threads;
    opts.sampler = a.sampler;
    opts.time_budget = a.time_budget;
    opts.progress = !a.quiet;
    opts.cancel = &g_cancel;
    install_signal_handlers();
    // The scene's notes (which model renders each subsurface object, and why) as well as warnings
    // and errors, unless --quiet.
    if (!a.quiet)
        pellucid::set_log_sink([](pellucid::LogLevel level, const std::string& msg) {
            if (level < pellucid::LogLevel::Info) return;
            const char* what = level >= pellucid::LogLevel::Error     ? "error"
                               : level >= pellucid::LogLevel::Warning ? "warning"
                                                                      : "info";
            std::fprintf(stderr, "pellucid: %s: %s\n", what, msg.c_str());
        });
    try {
        // Everything that can fail before rendering does: outputs, the state file, the scene.
        for (const auto& out : a.outputs) pellucid::check_image_output(out);
        const std::vector<pellucid::Aov> aovs = a.aovs.empty() ? std::vector<pellucid::Aov>{}
                                                               : pellucid::parse_aov_list(a.aovs, "--aovs");
        if (!aovs.empty() && std::none_of(a.outputs.begin(), a.outputs.end(), is_exr))
            throw pellucid::Error("--aovs: AOVs are written as layers of a multi-layer EXR: give an .exr OUTPUT");
        // The film estimates each pixel's variance only for the variance AOV: no other output reads
        // it, and a splatting film without it updates a third of the sums per splat.
        opts.variance = std::count(aovs.begin(), aovs.end(), pellucid::Aov::Variance) > 0;
        if (!a.resume.empty()) opts.resume = pellucid::load_film_state(a.resume);
        auto scene = pellucid::load_file(a.scene, a.lenient, params);
        pellucid::RenderResult r = a.aov.empty() ? pellucid::render(*scene, opts)
                                                 : pellucid::render_aov(*scene, a.aov, opts);
        const int sig = int(g_signal);
        const int interrupted_rc = 128 + (sig ? sig : SIGINT);
        if (r.stats.spp == 0) {
            std::fprintf(stderr, "%s: interrupted before the first pass finished; nothing written\n", kProg);
            return interrupted_rc;
        }
        // The AOV pass (skipped when the beauty render was interrupted: the image holds its passes).
        std::vector<pellucid::ImageLayer> layers;
        if (!aovs.empty() && !r.stats.cancelled) {
            bool aov_cancelled = false;
            double aov_seconds = 0.0;
            layers = pellucid::render_aovs(*scene, aovs, r, opts, &aov_cancelled, &aov_seconds);
            r.stats.cancelled = aov_cancelled;
            if (!a.quiet && !aov_cancelled) std::fprintf(stderr, "AOVs: %.3f s\n", aov_seconds);
        }
        if (!layers.empty()) layers.insert(layers.begin(), pellucid::ImageLayer{"", {"R", "G", "B"}, r.image});
        const auto attributes = pellucid::render_attributes(r);
        for (const auto& out : a.outputs) {
            if (!layers.empty() && is_exr(out)) pellucid::write_layers_file(out, layers, attributes);
            else pellucid::write_image(out, r.image, attributes);
            if (!a.quiet) std::fprintf(stderr, "wrote %s\n", out.c_str());
        }
        std::string state_path = a.state;
        if (state_path.empty() && r.stats.cancelled) state_path = a.outputs.front() + ".state";
        if (!state_path.empty()) {
            pellucid::save_film_state(state_path, *r.state);
            if (!a.quiet || r.stats.cancelled) std::fprintf(stderr, "wrote film state %s\n", state_path.c_str());
        }
        if (r.stats.invalid_samples)
            std::fprintf(stderr, "%s: warning: %llu NaN/Inf/negative samples were discarded\n", kProg,
                         (unsigned long long)r.stats.invalid_samples);
        if (!a.quiet)
            std::fprintf(stderr, "%d spp, %.3f s, %.3f M samples/s, %llu invalid samples dropped\n", r.stats.spp,
                         r.stats.seconds, double(r.stats.samples) / std::max(r.stats.seconds, 1e-9) * 1e-6,
                         (unsigned long long)r.stats.invalid_samples);
        if (r.stats.cancelled) {
            std::fprintf(stderr,
                         "%s: interrupted at %d spp; the image holds the complete passes (continue with --resume %s)\n",
                         kProg, r.stats.spp, state_path.c_str());
            return interrupted_rc;
        }
    } catch (const pellucid::Error& e) {
        std::fprintf(stderr, "%s: error: %s\n", kProg, e.what());
        return 1;
    } catch (const std::exception& e) {
        std::fprintf(stderr, "%s: internal error: %s\n", kProg, e.what());
        return 3;
    }
    return 0;
}
