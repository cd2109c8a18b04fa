// SPDX-License-Identifier: MIT
// QuadtreeBroadPhase's automatic tuning: when to re-tune, the bounds and depth it picks, and the rebuild.
#include "quadtree_broad_phase.h"

#include <algorithm>
#include <cmath>

namespace quadphase
{
namespace
{

// Percentile p (0..1) of values, reordering them.
float Percentile(std::vector<float>& values, double p)
{
    const size_t k = std::min(values.size() - 1, size_t(p * double(values.size() - 1) + 0.5));
    std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(k), values.end());
    return values[k];
}

// The range of `values` without its far outliers: from the lo to the hi percentile, widened to the extreme values
// that lie within a tenth of that span beyond it. The percentiles keep a few bodies flung far away from stretching
// the grid; the widening keeps the dense edge of a distribution (bodies piled against a container's walls) inside,
// where the percentiles alone cut a strip of it off and clamp that strip into the border cells.
void RobustRange(std::vector<float>& values, double lo, double hi, float& low, float& high)
{
    const float a = Percentile(values, lo);
    const float b = Percentile(values, hi);
    const float margin = 0.1f * (b - a);
    low = a;
    high = b;
    for (float v : values)
    {
        if (v < low && v >= a - margin)
        {
            low = v;
        }
        if (v > high && v <= b + margin)
        {
            high = v;
        }
    }
}

} // namespace

bool QuadtreeBroadPhase::NeedsRetune() const
{
    if (m_config.depth >= 0 && !m_config.autoBounds)
    {
        return false;
    }
    const int32_t n = m_pool.LiveCount();
    if ((n > 0 && n >= 2 * m_tunedCount) || (m_tunedCount > 64 && 4 * n < m_tunedCount))
    {
        return true;
    }
    // Counted from the last tuning: when retuning cannot bring proxies inside (boxes larger than the region the
    // centres span), the same retune would otherwise run again on every FindPairs.
    return m_config.autoBounds && n > 32 && m_pyramid.OutsideCount() - m_tunedOutside > n / 4;
}

// The automatic rule (docs/design.md, "Automatic depth and bounds"):
// - bounds: the box holding the centres of the proxies' fat boxes, from the 1st to the 99th percentile on each
//   axis when there are at least 200 proxies (so a few far-away bodies do not stretch the grid) widened to the
//   centres within a tenth of that span beyond it (RobustRange), grown on every side by the median fat-box extent,
//   made square around its centre;
// - depth: the smallest depth whose leaf side is at most cellToProxyRatio x the median fat-box extent, capped so
//   that the deepest level has at most 2 cells per proxy (4^depth <= 2 n) and by maxDepth.
void QuadtreeBroadPhase::Retune()
{
    const int32_t n = m_pool.LiveCount();
    std::vector<float> cx, cy, extent;
    cx.reserve(size_t(n));
    cy.reserve(size_t(n));
    extent.reserve(size_t(n));
    for (ProxyId id = 0; id < m_pool.IdBound(); ++id)
    {
        if (!m_pool.IsLive(id))
        {
            continue;
        }
        const Box& b = m_pool.Fat(id);
        if (!IsFinite(b) || !IsOrdered(b))
        {
            continue;
        }
        cx.push_back(0.5f * b.minX + 0.5f * b.maxX);
        cy.push_back(0.5f * b.minY + 0.5f * b.maxY);
        extent.push_back(std::max(b.maxX - b.minX, b.maxY - b.minY));
    }

    float originX, originY, side;
    float medianExtent = extent.empty() ? 1.0f : Percentile(extent, 0.5);
    if (!(medianExtent > 0.0f) || !std::isfinite(medianExtent))
    {
        medianExtent = 1.0f;
    }
    if (m_config.autoBounds)
    {
        if (cx.empty())
        {
            originX = m_config.bounds.minX;
            originY = m_config.bounds.minY;
            side = std::max(m_config.bounds.maxX - m_config.bounds.minX,
                            m_config.bounds.maxY - m_config.bounds.minY);
        }
        else
        {
            const double lo = cx.size() >= 200 ? 0.01 : 0.0;
            const double hi = cx.size() >= 200 ? 0.99 : 1.0;
            float x0, x1, y0, y1;
            RobustRange(cx, lo, hi, x0, x1);
            RobustRange(cy, lo, hi, y0, y1);
            // Made square around the centre of the percentile box, not from its lower corner: the extra room goes
            // to both sides of the shorter axis, where bodies are as likely to go (rain: the container below the
            // spawn rows was outside bounds that grew upward only, and the bodies piling in it crowded the border).
            side = std::max(x1 - x0, y1 - y0) + 2.0f * medianExtent;
            originX = 0.5f * x0 + 0.5f * x1 - 0.5f * side;
            originY = 0.5f * y0 + 0.5f * y1 - 0.5f * side;
        }
    }
    else
    {
        originX = m_config.bounds.minX;
        originY = m_config.bounds.minY;
        side = std::max(m_config.bounds.maxX - m_config.bounds.minX,
                        m_config.bounds.maxY - m_config.bounds.minY);
    }
    if (!(side > 0.0f) || !std::isfinite(side))
    {
        side = 1.0f;
    }

    int depth;
    if (m_config.depth >= 0)
    {
        depth = std::min(m_config.depth, kMaxDepth);
    }
    else
    {
        const float target = m_config.cellToProxyRatio * medianExtent;
        // Clamped before the conversion: a ratio <= 0 gives +inf (finest allowed) or NaN (0), and converting
        // either to int is undefined.
        const double want = std::ceil(std::log2(double(side) / double(target)));
        depth = want > 0.0 ? (want < double(kMaxDepth) ? int(want) : kMaxDepth) : 0;
        // 4^depth <= 2n  <=>  depth <= log2(2n) / 2
        const int memoryCap = int(std::floor(std::log2(2.0 * std::max(n, 1)) / 2.0));
        depth = std::max(0, std::min({depth, memoryCap, std::min(m_config.maxDepth, kMaxDepth)}));
    }
    m_tunedCount = n;
    Rebuild(originX, originY, side, depth);
    m_tunedOutside = m_pyramid.OutsideCount();
}

Pyramid QuadtreeBroadPhase::BuildPyramid(float originX, float originY, float side, int depth,
                                         Vec2 shift) const
{
    // Built beside the current pyramid and swapped in by CommitRebuild: std::bad_alloc half way leaves the current
    // one intact (the price is both in memory at once, for the length of a rebuild).
    Pyramid built;
    built.Reset(originX, originY, side, depth);
    for (ProxyId id = 0; id < m_pool.IdBound(); ++id)
    {
        if (m_pool.IsLive(id))
        {
            const Box& b = m_pool.Fat(id);
            built.Insert(id, Box{b.minX - shift.x, b.minY - shift.y, b.maxX - shift.x, b.maxY - shift.y});
        }
    }
    built.Compact(); // cells in row-major order in memory: neighbouring cells are read together
    return built;
}

void QuadtreeBroadPhase::Rebuild(float originX, float originY, float side, int depth)
{
    CommitRebuild(BuildPyramid(originX, originY, side, depth, Vec2{0.0f, 0.0f}));
}

void QuadtreeBroadPhase::CommitRebuild(Pyramid&& built)
{
    m_pyramid.ReplaceWith(std::move(built));
    // Every entry was just written from the current boxes.
    for (ProxyId id : m_stale)
    {
        m_pool.ClearStale(id);
    }
    m_stale.clear();
    NoteStale();
    ++m_mutations;
    m_counters.rebuilds += 1;
}

} // namespace quadphase
