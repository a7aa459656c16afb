// libFuzzer harness: a JSON scene file through the reader, the scene builder and a 1-spp render of
// films up to 32x32 pixels. Relative file names resolve against bench/fuzz/assets.
// SPDX-License-Identifier: Apache-2.0
#include "fuzz_common.h"
#include "fuzz_scene.h"
#include "pellucid/scene/json_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    fuzz::scratch_dir();
    if (fuzz::names_special_file(data, size)) return -1;
    fuzz::expect_only_errors([&] {
        pellucid::SceneDesc desc;
        desc.root = pellucid::parse_json(std::string(reinterpret_cast<const char*>(data), size), "fuzz.json");
        desc.source = "fuzz.json";
        desc.base_dir = PELLUCID_FUZZ_ASSETS;
        fuzz::build_and_render(desc);
    });
    return 0;
}
