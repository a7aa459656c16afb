// libFuzzer harness: an OBJ file through the mesh reader and the mesh checks.
// SPDX-License-Identifier: Apache-2.0
#include "fuzz_common.h"
#include "pellucid/geometry/mesh.h"
#include "pellucid/geometry/mesh_io.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string path = fuzz::write_file("input.obj", data, size);
    fuzz::expect_only_errors([&] {
        pellucid::MeshLoadOptions opt;
        opt.smooth_normals = size > 0 && (data[0] & 1);
        pellucid::ObjMesh m = pellucid::load_obj(path, opt);
        m.mesh.validate("input.obj: ");
    });
    return 0;
}
