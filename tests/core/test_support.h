// SPDX-License-Identifier: MIT
// Helpers shared by the core tests: random boxes, the error-handler guard, pair and id collection.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "broad_phase_interface.h"
#include "quadphase/box.h"
#include "report_error.h"

namespace qptest
{

using quadphase::Box;
using quadphase::ErrorCode;
using quadphase::Pair;
using quadphase::ProxyId;
using quadphase::Vec2;

// ---------------------------------------------------------------------------------------------------------------
// Bits and printing

inline uint32_t Bits(float f)
{
    uint32_t u;
    std::memcpy(&u, &f, sizeof(u));
    return u;
}

/// Bitwise equality of two floats (so +0 != -0), except that any two NaNs compare equal.
inline bool SameFloat(float a, float b)
{
    if (std::isnan(a) || std::isnan(b))
    {
        return std::isnan(a) && std::isnan(b);
    }
    return Bits(a) == Bits(b);
}

inline bool SameBox(const Box& a, const Box& b)
{
    return SameFloat(a.minX, b.minX) && SameFloat(a.minY, b.minY) && SameFloat(a.maxX, b.maxX) &&
           SameFloat(a.maxY, b.maxY);
}

inline std::string Str(const Box& b)
{
    std::ostringstream os;
    os.precision(9);
    os << "(" << b.minX << ", " << b.minY << ")-(" << b.maxX << ", " << b.maxY << ")";
    return os.str();
}

// ---------------------------------------------------------------------------------------------------------------
// Error handler guard: counts reports per code, restores the previous handler on destruction.

class ErrorCounter
{
public:
    ErrorCounter() { m_previous = quadphase::SetErrorHandler(&ErrorCounter::Handle, this); }
    ~ErrorCounter() { quadphase::SetErrorHandler(m_previous); }
    ErrorCounter(const ErrorCounter&) = delete;
    ErrorCounter& operator=(const ErrorCounter&) = delete;

    int Count(ErrorCode code) const
    {
        const auto it = m_counts.find(code);
        return it == m_counts.end() ? 0 : it->second;
    }
    int Total() const
    {
        int total = 0;
        for (const auto& entry : m_counts)
        {
            total += entry.second;
        }
        return total;
    }
    const std::string& LastMessage() const { return m_last; }
    ErrorCode LastCode() const { return m_lastCode; }
    void Reset()
    {
        m_counts.clear();
        m_last.clear();
    }

private:
    // The core's three codes, then one slot for every engine adapter code.

    static void Handle(ErrorCode code, const char* message, void* context)
    {
        ErrorCounter* self = static_cast<ErrorCounter*>(context);
        self->m_counts[code] += 1;
        self->m_last = message;
        self->m_lastCode = code;
    }

    quadphase::ErrorHandler m_previous = nullptr;
    std::map<ErrorCode, int> m_counts;
    std::string m_last;
    ErrorCode m_lastCode = ErrorCode::FirstAdapterCode;
};

// ---------------------------------------------------------------------------------------------------------------
// Collecting results

inline std::vector<Pair> Sorted(std::vector<Pair> pairs)
{
    std::sort(pairs.begin(), pairs.end());
    return pairs;
}

inline bool HasDuplicates(const std::vector<Pair>& sorted)
{
    return std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end();
}

inline bool AllOrdered(const std::vector<Pair>& pairs)
{
    for (const Pair& p : pairs)
    {
        if (!(p.a < p.b))
        {
            return false;
        }
    }
    return true;
}

inline std::string Str(const std::vector<Pair>& pairs, size_t limit = 40)
{
    std::ostringstream os;
    os << pairs.size() << " pairs:";
    for (size_t i = 0; i < pairs.size() && i < limit; ++i)
    {
        os << " (" << pairs[i].a << "," << pairs[i].b << ")";
    }
    if (pairs.size() > limit)
    {
        os << " ...";
    }
    return os.str();
}

/// Pairs in `a` but not in `b` (both sorted), for failure messages.
inline std::vector<Pair> Difference(const std::vector<Pair>& a, const std::vector<Pair>& b)
{
    std::vector<Pair> d;
    std::set_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(d));
    return d;
}

struct IdCollector
{
    std::vector<ProxyId> ids;
    int calls = 0;
    int stopAfter = -1; // stop (return false) once `calls` reaches it; -1: never

    static bool Callback(void* context, ProxyId id)
    {
        IdCollector* self = static_cast<IdCollector*>(context);
        self->ids.push_back(id);
        self->calls += 1;
        return !(self->stopAfter >= 0 && self->calls >= self->stopAfter);
    }

    std::vector<ProxyId> SortedIds() const
    {
        std::vector<ProxyId> s = ids;
        std::sort(s.begin(), s.end());
        return s;
    }
};

// ---------------------------------------------------------------------------------------------------------------
// Random numbers

using Rng = std::mt19937;

inline float Uniform(Rng& rng, float lo, float hi)
{
    return std::uniform_real_distribution<float>(lo, hi)(rng);
}

inline int UniformInt(Rng& rng, int lo, int hi) // inclusive
{
    return std::uniform_int_distribution<int>(lo, hi)(rng);
}

inline bool Chance(Rng& rng, double p)
{
    return std::bernoulli_distribution(p)(rng);
}

/// 10^u, u uniform in [lo, hi].
inline float LogUniform(Rng& rng, float lo, float hi)
{
    return std::pow(10.0f, Uniform(rng, lo, hi));
}

inline float Gaussian(Rng& rng, float sigma)
{
    return std::normal_distribution<float>(0.0f, sigma)(rng);
}

/// Box with the given centre and half extents.
inline Box CentredBox(float cx, float cy, float hx, float hy)
{
    return Box{cx - hx, cy - hy, cx + hx, cy + hy};
}

/// The distributions the differential tests draw tight boxes from.
enum class Dist
{
    Uniform,   // uniform centres over the world, sizes uniform in [0.1, 4]
    LogMixed,  // sizes log-uniform in [1e-3, 1e3]
    Clustered, // a few tight Gaussian clusters
    Outside,   // centres spread 4x wider than the fixed bounds: mostly outside
    ZeroArea,  // points and segments, coordinates often on a lattice (cell borders)
    Huge,      // mostly ordinary boxes plus boxes far larger than the world
    Mixed,     // each box from any of the above
};

inline const char* DistName(Dist d)
{
    // In Dist's order.
    static const char* const kNames[] = {"uniform",   "log-mixed", "clustered", "outside",
                                         "zero-area", "huge",      "mixed"};
    const size_t i = size_t(d);
    return i < sizeof(kNames) / sizeof(kNames[0]) ? kNames[i] : "?";
}

constexpr Dist kAllDists[] = {Dist::Uniform,  Dist::LogMixed, Dist::Clustered, Dist::Outside,
                              Dist::ZeroArea, Dist::Huge,     Dist::Mixed};

/// Draws tight boxes. `world` is the half side of the region most boxes live in.
class BoxSource
{
public:
    BoxSource(Rng& rng, Dist dist, float world) : m_rng(rng), m_dist(dist), m_world(world)
    {
        const int clusters = UniformInt(rng, 1, 5);
        for (int i = 0; i < clusters; ++i)
        {
            m_clusters.push_back(Vec2{Uniform(rng, -world, world), Uniform(rng, -world, world)});
            m_sigmas.push_back(LogUniform(rng, -1.0f, 0.7f));
        }
        m_lattice = std::ldexp(1.0f, UniformInt(rng, -3, 3)); // 0.125 .. 8
    }

    Dist GetDist() const { return m_dist; }

    Box Next() { return Next(m_dist); }

    Box Next(Dist d)
    {
        Rng& r = m_rng;
        const float w = m_world;
        switch (d)
        {
        case Dist::Uniform:
            return CentredBox(Uniform(r, -w, w), Uniform(r, -w, w), Uniform(r, 0.05f, 2.0f),
                              Uniform(r, 0.05f, 2.0f));
        case Dist::LogMixed:
        {
            const float s = LogUniform(r, -3.0f, 3.0f);
            const float aspect = LogUniform(r, -1.0f, 1.0f);
            return CentredBox(Uniform(r, -w, w), Uniform(r, -w, w), 0.5f * s * aspect, 0.5f * s / aspect);
        }
        case Dist::Clustered:
        {
            const size_t c = size_t(UniformInt(r, 0, int(m_clusters.size()) - 1));
            const float sigma = m_sigmas[c];
            return CentredBox(m_clusters[c].x + Gaussian(r, sigma), m_clusters[c].y + Gaussian(r, sigma),
                              Uniform(r, 0.01f, 0.5f), Uniform(r, 0.01f, 0.5f));
        }
        case Dist::Outside:
            return CentredBox(Uniform(r, -4.0f * w, 4.0f * w), Uniform(r, -4.0f * w, 4.0f * w),
                              LogUniform(r, -2.0f, 1.0f), LogUniform(r, -2.0f, 1.0f));
        case Dist::ZeroArea:
        {
            float x = Uniform(r, -w, w);
            float y = Uniform(r, -w, w);
            if (Chance(r, 0.6))
            {
                x = std::round(x / m_lattice) * m_lattice;
                y = std::round(y / m_lattice) * m_lattice;
            }
            const int kind = UniformInt(r, 0, 3);
            float lx = 0.0f, ly = 0.0f;
            if (kind == 1 || kind == 3)
            {
                lx = Chance(r, 0.5) ? m_lattice * float(UniformInt(r, 1, 4)) : Uniform(r, 0.0f, 3.0f);
            }
            if (kind == 2 || kind == 3)
            {
                ly = Chance(r, 0.5) ? m_lattice * float(UniformInt(r, 1, 4)) : Uniform(r, 0.0f, 3.0f);
            }
            if (kind == 3)
            {
                // a segment: zero extent on one axis
                (Chance(r, 0.5) ? lx : ly) = 0.0f;
            }
            return Box{x, y, x + lx, y + ly};
        }
        case Dist::Huge:
            if (Chance(r, 0.15))
            {
                const float s = LogUniform(r, 3.0f, 6.0f);
                return CentredBox(Uniform(r, -w, w), Uniform(r, -w, w), s * Uniform(r, 0.5f, 1.0f),
                                  s * Uniform(r, 0.5f, 1.0f));
            }
            return Next(Dist::Uniform);
        case Dist::Mixed:
            return Next(kAllDists[UniformInt(r, 0, 5)]);
        }
        return Box{0, 0, 0, 0};
    }

    /// A displacement: zero, tiny, ordinary or large.
    Vec2 Displacement()
    {
        Rng& r = m_rng;
        switch (UniformInt(r, 0, 5))
        {
        case 0:
            return Vec2{0.0f, 0.0f};
        case 1:
            return Vec2{Uniform(r, -1e-5f, 1e-5f), Uniform(r, -1e-5f, 1e-5f)};
        case 2:
        case 3:
            return Vec2{Uniform(r, -0.2f, 0.2f), Uniform(r, -0.2f, 0.2f)};
        case 4:
            return Vec2{Uniform(r, -3.0f, 3.0f), Uniform(r, -3.0f, 3.0f)};
        default:
            return Vec2{Uniform(r, -m_world, m_world), Uniform(r, -m_world, m_world)};
        }
    }

private:
    Rng& m_rng;
    Dist m_dist;
    float m_world;
    std::vector<Vec2> m_clusters;
    std::vector<float> m_sigmas;
    float m_lattice = 1.0f;
};

inline Box Translate(const Box& b, Vec2 d)
{
    return Box{b.minX + d.x, b.minY + d.y, b.maxX + d.x, b.maxY + d.y};
}

} // namespace qptest
