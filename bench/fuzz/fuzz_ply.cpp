// libFuzzer harness: a PLY file (ASCII or binary) through the mesh reader and the mesh checks.
// SPDX-License-Identifier: Apache-2.0
#include "fuzz_common.h"
#include "pellucid/geometry/mesh.h"
#include "pellucid/geometry/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = fuzz::write_file("input.ply", data, size);
    fuzz::expect_only_errors([&] {
        pellucid::MeshLoadOptions opt;
        opt.smooth_normals = size > 0 && (data[size - 1] & 1);
        pellucid::TriangleMesh m = pellucid::load_ply(path, opt);
        m.validate("input.ply: ");
    });
    return 0;
}
