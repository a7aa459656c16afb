// libFuzzer harness: a Mitsuba 3 XML scene through the importer (strict and lenient), the scene
// builder and a 1-spp render of films up to 32x32 pixels. Relative file names resolve against
// bench/fuzz/assets.
// SPDX-License-Identifier: Apache-2.0
#include "fuzz_common.h"
#include "fuzz_scene.h"
#include "pellucid/scene/mitsuba_xml.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    fuzz::scratch_dir();
    if (fuzz::names_special_file(data, size)) return -1;
    const std::string text(reinterpret_cast<const char*>(data), size);
    // The first byte picks strict or lenient import, so both modes see every kind of input.
    const bool lenient = size > 0 && (data[0] & 1);
    fuzz::expect_only_errors([&] {
        pellucid::SceneDesc desc = pellucid::parse_mitsuba_xml(text, "fuzz.xml", PELLUCID_FUZZ_ASSETS, lenient);
        fuzz::build_and_render(desc);
    });
    return 0;
}
