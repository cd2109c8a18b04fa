// SPDX-License-Identifier: MIT
// Reading a fuzz input as a program: the byte reader and the box and ray generators that both fuzz targets
// (broadphase_fuzz.cpp, box2d_fuzz.cpp) share, so that the same bytes mean the same shapes in both.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <utility>

#include "fuzz_stats.h"
#include "quadphase/box.h"
#include "quadphase/error.h"
#include "ray.h"

namespace quadphase
{
namespace fuzz
{

/// Reads bytes in order. A short input is a valid program: reading past the end yields zeros (Done() tells).
class Reader
{
public:
    Reader(const uint8_t* data, size_t size) : m_data(data), m_size(size) {}
    bool Done() const { return m_pos >= m_size; }
    uint8_t Byte() { return m_pos < m_size ? m_data[m_pos++] : 0; }
    uint16_t U16()
    {
        const uint16_t lo = Byte();
        return uint16_t(lo | (uint16_t(Byte()) << 8));
    }
    /// In [-1, 1].
    float Signed() { return float(int(U16()) - 32768) / 32768.0f; }
    /// In [0, 1].
    float Unit() { return float(U16()) / 65535.0f; }
    /// Any float, bit for bit (NaN and infinities included): 4 bytes, little-endian.
    float Raw()
    {
        uint32_t bits = 0;
        for (int i = 0; i < 4; ++i)
        {
            bits |= uint32_t(Byte()) << (8 * i);
        }
        float f;
        std::memcpy(&f, &bits, sizeof f);
        return f;
    }

private:
    const uint8_t* m_data;
    size_t m_size;
    size_t m_pos = 0;
};

/// Mode byte of a box given bit for bit (kRawBox, then 4 floats: minX, minY, maxX, maxY), as the trace
/// converter writes recorded boxes, and as mutations reach any float.
constexpr uint8_t kRawBox = 0xfd;

/// Makes a raw box usable where bad boxes are not allowed: non-finite coordinates become 0, then each axis is
/// put in order.
inline Box SaneBox(Box b)
{
    float* v[4] = {&b.minX, &b.minY, &b.maxX, &b.maxY};
    for (float* f : v)
    {
        if (!std::isfinite(*f))
        {
            *f = 0.0f;
        }
    }
    if (b.minX > b.maxX)
    {
        std::swap(b.minX, b.maxX);
    }
    if (b.minY > b.maxY)
    {
        std::swap(b.minY, b.maxY);
    }
    return b;
}

/// A tight box in one of several scales (0.01 m to 1e6 m from the origin, zero-size on one axis or both), or
/// given bit for bit (kRawBox). With `allowBad`, about one in a hundred is bad (NaN, infinite, inverted), and
/// raw boxes are taken as they are; without it, every box is finite and ordered. `sane` tells whether the
/// result is finite and ordered. Reads the same bytes whatever `allowBad` says.
inline Box ReadBox(Reader& in, bool allowBad, bool& sane)
{
    const uint8_t mode = in.Byte();
    if (mode == kRawBox)
    {
        Box raw{in.Raw(), in.Raw(), in.Raw(), in.Raw()};
        if (!allowBad)
        {
            raw = SaneBox(raw);
        }
        sane = IsSane(raw);
        return raw;
    }
    const float scales[] = {8.0f, 64.0f, 1000.0f, 1.0e5f, 1.0e6f, 0.5f};
    const float centreScale = scales[(mode >> 4) % 6];
    const float cx = in.Signed() * centreScale;
    const float cy = in.Signed() * centreScale;
    float hx = in.Unit() * ((mode & 1) != 0 ? 20.0f : 2.0f);
    float hy = in.Unit() * ((mode & 2) != 0 ? 20.0f : 2.0f);
    if ((mode & 12) == 12)
    {
        hx = 0.0f; // zero-size (on one axis or both)
        hy = (mode & 64) != 0 ? 0.0f : hy;
    }
    Box b{cx - hx, cy - hy, cx + hx, cy + hy};
    sane = true;
    if (mode == 0xff || mode == 0xfe)
    {
        const uint8_t kind = in.Byte();
        if (allowBad)
        {
            const float nan = std::numeric_limits<float>::quiet_NaN();
            const float inf = std::numeric_limits<float>::infinity();
            switch (kind % 4)
            {
            case 0:
                b.minX = nan;
                break;
            case 1:
                b.maxY = inf;
                break;
            case 2:
                b = Box{-inf, -inf, inf, inf};
                break;
            default:
                b = Box{b.maxX + 1.0f, b.minY, b.minX, b.maxY}; // inverted on x
                break;
            }
            sane = false;
        }
    }
    return b;
}

/// A segment: short (within 64 m) or long (within 1 km), any direction, maxFraction in [0, 1.5]; p1 != p2.
inline RayInput ReadRay(Reader& in)
{
    const uint8_t mode = in.Byte();
    const float scale = (mode & 1) != 0 ? 1000.0f : 64.0f;
    RayInput ray{{in.Signed() * scale, in.Signed() * scale},
                 {in.Signed() * scale, in.Signed() * scale},
                 in.Unit() * 1.5f};
    if ((mode & 6) == 6)
    {
        ray.p2.y = ray.p1.y; // axis-aligned: the walk's row-by-row case
    }
    if (ray.p1.x == ray.p2.x && ray.p1.y == ray.p2.y)
    {
        ray.p2.x += 1.0f; // Box2D requires p1 != p2
    }
    return ray;
}

/// LLVMFuzzerTestOneInput's body for both targets: runs `data` as a program of `Run` (built from the first
/// byte and a Scratch reused across inputs, so that no operation allocates once the buffers have grown) with
/// `handler` as quadphase's error hook.
template <typename Run, typename Scratch>
int RunProgram(const uint8_t* data, size_t size, ErrorHandler handler)
{
    if (size == 0)
    {
        return 0;
    }
    static Scratch scratch;
    const ErrorHandler previous = SetErrorHandler(handler);
    Reader in(data, size);
    {
        Run run(in.Byte(), scratch);
        run.Execute(in);
    }
    SetErrorHandler(previous);
    ++g_stats.inputs;
    return 0;
}

} // namespace fuzz
} // namespace quadphase
