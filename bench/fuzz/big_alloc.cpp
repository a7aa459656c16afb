// Linked into the image harness only: the global operator new/delete route blocks of 16 MB and more
// to mmap, past AddressSanitizer's allocator; smaller blocks go to malloc, which ASan still
// instruments.
//
// Why: OpenImageIO's ImageInput::read_scanlines, whenever it converts pixel formats, allocates a
// buffer for about 64 MB of scanlines however few it reads (an 8-pixel-wide image gets 32 MB). An
// image input goes through it two to four times (texel scan, sRGB conversion, the texture cache's
// tile read). Under ASan each such block costs tens of megabytes of shadow-memory writes and page
// faults on allocation, free and recycling: 80 % of the harness's time, about 20 executions per
// second. OpenImageIO is not instrumented, and it touches only the first rows of these buffers, so
// ASan checks nothing in them that matters; pellucid's own buffers stay far below 16 MB (the texel
// scan reads bands of 4 MB) and stay instrumented.
//
// Lost: ASan's new/delete mismatch reports (new paired with free) for every size, and overflow
// checks on blocks of 16 MB and more. Aligned new/delete (std::align_val_t) keep ASan's versions.
// SPDX-License-Identifier: Apache-2.0
#include <sanitizer/allocator_interface.h>
#include <sys/mman.h>

#include <cstddef>
#include <cstdlib>
#include <new>

namespace {
constexpr std::size_t kBig = std::size_t(16) << 20;
constexpr std::size_t kHeader = 64;  // keeps the 16-byte alignment new must give; holds the size

void* allocate(std::size_t n) noexcept {
    if (n < kBig) return std::malloc(n ? n : 1);
    void* p = mmap(nullptr, n + kHeader, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) return nullptr;
    *static_cast<std::size_t*>(p) = n + kHeader;
    return static_cast<char*>(p) + kHeader;
}

void release(void* p) noexcept {
    if (!p) return;
    if (__sanitizer_get_ownership(p)) {  // from malloc above
        std::free(p);
        return;
    }
    void* base = static_cast<char*>(p) - kHeader;
    munmap(base, *static_cast<std::size_t*>(base));
}

void* allocate_or_throw(std::size_t n) {
    void* p = allocate(n);
    if (!p) throw std::bad_alloc();
    return p;
}
}  // namespace

void* operator new(std::size_t n) { return allocate_or_throw(n); }
void* operator new[](std::size_t n) { return allocate_or_throw(n); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return allocate(n); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return allocate(n); }
void operator delete(void* p) noexcept { release(p); }
void operator delete[](void* p) noexcept { release(p); }
void operator delete(void* p, std::size_t) noexcept { release(p); }
void operator delete[](void* p, std::size_t) noexcept { release(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { release(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { release(p); }
