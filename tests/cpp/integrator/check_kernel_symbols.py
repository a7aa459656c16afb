"""Check that a per-target kernel object (cpp/pellucid/integrator/kernels/kernel_<target>.cpp, built
with that instruction set's flags) exports nothing another object could also define.

An inline function or template instantiation emitted in two objects is merged by the linker, which
keeps one copy; if it kept the AVX-512 copy of a function the scalar library also calls, a CPU
without AVX-512 would fault. So every global or weak symbol of a kernel object must either be its
entry point or name the target's xsimd architecture among its template arguments (then no other
object can define it). Usage: check_kernel_symbols.py TARGET ENTRY OBJECT..., ENTRY the entry point's
qualified name (pellucid::render_tile_avx512).
SPDX-License-Identifier: Apache-2.0
"""
import subprocess
import sys

ARCH = {"avx512": "xsimd::avx512bw", "avx2": "xsimd::avx2", "sse4": "xsimd::sse4_2", "neon": "xsimd::neon64"}
ALLOWED = {"DW.ref.__gxx_personality_v0"}


def main(argv):
    target, entry, objects = argv[1], argv[2] + "(", argv[3:]
    bad, entries = [], 0
    for obj in objects:
        out = subprocess.run(["nm", "-C", "--defined-only", obj], capture_output=True, text=True, check=True).stdout
        for line in out.splitlines():
            parts = line.split(None, 2)
            if len(parts) < 3:
                continue
            kind, name = parts[1], parts[2]
            if kind.islower() and kind not in ("u", "v", "w"):
                continue  # local to the object
            if name.startswith(entry):
                entries += 1
            elif name not in ALLOWED and ARCH[target] not in name:
                bad.append(f"{kind} {name}")
    if entries != 1:
        print(f"expected one entry point {entry}...), found {entries}")
        return 1
    if bad:
        print(f"{len(bad)} symbol(s) of the {target} kernel could clash with another object's:")
        print("\n".join(bad[:50]))
        return 1
    print(f"{target}: only the entry point and {ARCH[target]} instantiations are global")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
