// SPDX-License-Identifier: MIT
// RayWalk: the cells of the static quadtree that a segment's proxies can live in, level by level, in the ray's
// direction (QuadtreeBroadPhase::RayCast; private to the core's sources).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "pyramid.h"
#include "ray.h"

namespace quadphase
{
namespace detail
{

// The cells a segment's proxies can live in, level by level: see QuadtreeBroadPhase::RayCast and docs/design.md
// ("Ray casts"). Works in deepest-level cell units ("leaf units"), in double.
class RayWalk
{
public:
    RayWalk(const Pyramid& pyramid, const RayInput& input)
    {
        const double invLeaf = double(pyramid.InvLeaf());
        const double ox = double(pyramid.OriginX());
        const double oy = double(pyramid.OriginY());
        m_u0 = (double(input.p1.x) - ox) * invLeaf;
        m_v0 = (double(input.p1.y) - oy) * invLeaf;
        m_du = (double(input.p2.x) - double(input.p1.x)) * invLeaf;
        m_dv = (double(input.p2.y) - double(input.p1.y)) * invLeaf;
        m_invDv = m_dv != 0.0 ? 1.0 / m_dv : 0.0;
        m_max = double(pyramid.MaxCoord());
        m_depth = pyramid.Depth();
        m_eps = RoundingSlack(pyramid, input, invLeaf);
        m_valid = Moderate(input) && std::isfinite(m_u0) && std::isfinite(m_v0) && std::isfinite(m_du) &&
                  std::isfinite(m_dv) && std::isfinite(m_eps) && (m_du != 0.0 || m_dv != 0.0);
    }

    /// False for segments the walk cannot follow (non-finite, zero length, coordinates beyond 1e18): use the
    /// bounding box instead.
    bool Valid() const { return m_valid; }

    /// Cells the walk of `level` reads, about, up to fraction t.
    int64_t Cost(int level, double t) const
    {
        const double cs = CellSize(level);
        const double w = std::fabs(Clamp(m_u0 + t * m_du) - Clamp(m_u0)) / cs;
        const double z = std::fabs(Clamp(m_v0 + t * m_dv) - Clamp(m_v0)) / cs;
        return int64_t(std::min(2.0 * w + 3.0 * z + 9.0, 4e18));
    }

    /// Stored rows of `level` in the ray's direction: from First(level) to Last(level, t) (inclusive), stepping by
    /// Step(). Last moves toward First as the segment is clipped.
    int32_t First(int level) const
    {
        const double z = Clamp(m_v0) / CellSize(level);
        const double e = Slack(level);
        return ClampRow(level, m_dv >= 0.0 ? Floor(z - e) - 1 : Floor(z + e));
    }
    int32_t Last(int level, double t) const
    {
        const double z = Clamp(m_v0 + t * m_dv) / CellSize(level);
        const double e = Slack(level);
        return ClampRow(level, m_dv >= 0.0 ? Floor(z + e) : Floor(z - e) - 1);
    }
    int32_t Step() const { return m_dv >= 0.0 ? 1 : -1; }

    /// The columns [x0, x1] of stored row r of `level` whose proxies the segment up to fraction t may reach; false
    /// when there are none. A proxy stored in cell (cx, cy) lies, in clamped coordinates, within cells cx..cx+1 and
    /// cy..cy+1 (Pyramid's placement rule), so row r's proxies are reached only by points of the segment whose
    /// clamped row is r or r + 1; their columns, less one, bound the stored columns.
    bool Columns(int level, int32_t r, double t, int32_t& x0, int32_t& x1) const
    {
        double ta, tb;
        if (!RowSpan(level, r, t, ta, tb))
        {
            return false;
        }
        const double cs = CellSize(level);
        const double invCs = 1.0 / cs; // exact: a power of two
        const double e = Slack(level) * cs;
        const double ua = m_u0 + ta * m_du;
        const double ub = m_u0 + tb * m_du;
        const int32_t side = LevelSide(level);
        x0 = std::max(0, Floor(Clamp(std::min(ua, ub) - e) * invCs) - 1);
        x1 = std::min(side - 1, Floor(Clamp(std::max(ua, ub) + e) * invCs));
        return x0 <= x1;
    }

    /// True when the ray runs toward smaller x (columns are then walked from x1 down to x0).
    bool Backward() const { return m_du < 0.0; }

private:
    // Slack for float rounding, in leaf units. The proxies' cells come from float coordinates and the segment test
    // (SegmentTest::MayCross) runs in float, so a box the exact segment misses by a few ulps may still pass it; such
    // a box must lie in a walked cell. Errors there are a few ulps (2^-23 relative) of the magnitudes involved;
    // 2^-19 of their sum, plus a thousandth of a cell, is a wide margin.
    static double RoundingSlack(const Pyramid& pyramid, const RayInput& input, double invLeaf)
    {
        const double magnitude = std::fabs(double(pyramid.OriginX())) + std::fabs(double(pyramid.OriginY())) +
                                 2.0 * double(pyramid.Bounds().maxX - pyramid.Bounds().minX) +
                                 std::fabs(double(input.p1.x)) + std::fabs(double(input.p1.y)) +
                                 std::fabs(double(input.p2.x)) + std::fabs(double(input.p2.y));
        return 1e-3 + magnitude * invLeaf * (1.0 / 524288.0);
    }

    // Beyond 1e18 the float arithmetic of SegmentTest overflows (the segment's squared length is infinite, its
    // normal becomes zero, and every box its bounding box touches passes MayCross, as in stock's tree): only the
    // bounding box then finds every candidate.
    static bool Moderate(const RayInput& input)
    {
        const float kMaxCoord = 1e18f;
        return std::fabs(input.p1.x) <= kMaxCoord && std::fabs(input.p1.y) <= kMaxCoord &&
               std::fabs(input.p2.x) <= kMaxCoord && std::fabs(input.p2.y) <= kMaxCoord;
    }

    // The fractions [ta, tb] within [0, t] where the segment's clamped row is r or r + 1 (widened by the slack);
    // false when there are none.
    bool RowSpan(int level, int32_t r, double t, double& ta, double& tb) const
    {
        const double cs = CellSize(level);
        const double e = Slack(level) * cs;
        const double inf = std::numeric_limits<double>::infinity();
        // The band of unclamped v whose clamped value lies in rows [r, r + 2), widened by the slack.
        const double vLo = double(r) * cs - e <= 0.0 ? -inf : double(r) * cs - e;
        const double vHi = double(r + 2) * cs + e >= m_max ? inf : double(r + 2) * cs + e;
        ta = 0.0;
        tb = t;
        if (m_dv == 0.0)
        {
            return vLo <= m_v0 && m_v0 <= vHi && ta <= tb;
        }
        // By the inverse, not a division per row: a few ulps of t, far inside the slack.
        double t1 = (vLo - m_v0) * m_invDv;
        double t2 = (vHi - m_v0) * m_invDv;
        if (t1 > t2)
        {
            std::swap(t1, t2);
        }
        ta = std::max(ta, t1);
        tb = std::min(tb, t2);
        return ta <= tb;
    }

    double CellSize(int level) const { return double(int64_t(1) << (m_depth - level)); }
    // Slack in cells of `level`: the leaf-unit slack, plus 2^-16 of a cell for the division by the cell size.
    double Slack(int level) const { return m_eps / CellSize(level) + (1.0 / 65536.0); }
    double Clamp(double u) const { return u < 0.0 ? 0.0 : (u > m_max ? m_max : u); }
    // floor() clamped to +-1e9, without libm's floor (a call on baseline x86-64, which has no roundsd): truncation,
    // minus one for negative non-integers.
    static int32_t Floor(double x)
    {
        if (!(x > -1e9))
        {
            return -1000000000;
        }
        if (!(x < 1e9))
        {
            return 1000000000;
        }
        const int32_t i = int32_t(x);
        return double(i) > x ? i - 1 : i;
    }
    static int32_t ClampRow(int level, int32_t r) { return std::max(0, std::min(LevelSide(level) - 1, r)); }

    double m_u0 = 0.0, m_v0 = 0.0, m_du = 0.0, m_dv = 0.0, m_invDv = 0.0, m_max = 0.0, m_eps = 0.0;
    int m_depth = 0;
    bool m_valid = false;
};

} // namespace detail
} // namespace quadphase
