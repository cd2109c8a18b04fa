// SPDX-License-Identifier: MIT
// Segment queries with the same arithmetic as Box2D 2.4.1's b2DynamicTree::RayCast, so that the same boxes
// pass the same tests.
#pragma once

#include <cmath>

#include "quadphase/box.h"

namespace quadphase
{

/// A segment from p1 toward p2; only the part p1 -> p1 + maxFraction * (p2 - p1) is searched.
struct RayInput
{
    Vec2 p1;
    Vec2 p2;
    float maxFraction;
};

/// The precomputed parts of a segment test. Build it once per ray cast, clip it when the callback shortens the ray.
class SegmentTest
{
public:
    /// Requires p1 != p2 (Box2D asserts the same).
    explicit SegmentTest(const RayInput& input) : m_p1(input.p1)
    {
        float rx = input.p2.x - input.p1.x;
        float ry = input.p2.y - input.p1.y;
        // b2Vec2::Normalize: length computed in float, then scaled by its inverse.
        const float length = std::sqrt(rx * rx + ry * ry);
        if (length >= 1.1920928955078125e-07f) // b2_epsilon
        {
            const float inv = 1.0f / length;
            rx *= inv;
            ry *= inv;
        }
        // v = b2Cross(1.0f, r) = (-r.y, r.x), perpendicular to the segment.
        m_vx = -ry;
        m_vy = rx;
        m_absVx = std::fabs(m_vx);
        m_absVy = std::fabs(m_vy);
        m_dx = input.p2.x - input.p1.x;
        m_dy = input.p2.y - input.p1.y;
        Clip(input.maxFraction);
    }

    /// Shortens the searched part of the segment to p1 -> p1 + maxFraction * (p2 - p1).
    void Clip(float maxFraction)
    {
        m_maxFraction = maxFraction;
        const float tx = m_p1.x + maxFraction * m_dx;
        const float ty = m_p1.y + maxFraction * m_dy;
        m_bounds = Box{m_p1.x < tx ? m_p1.x : tx, m_p1.y < ty ? m_p1.y : ty, m_p1.x < tx ? tx : m_p1.x,
                       m_p1.y < ty ? ty : m_p1.y};
    }

    /// True when the searched part of the segment may cross `box` (b2DynamicTree's overlap and separating-axis
    /// tests, with its arithmetic).
    bool MayCross(const Box& box) const
    {
        if (!(box.minX <= m_bounds.maxX && m_bounds.minX <= box.maxX && box.minY <= m_bounds.maxY &&
              m_bounds.minY <= box.maxY))
        {
            return false;
        }
        const float cx = 0.5f * (box.minX + box.maxX);
        const float cy = 0.5f * (box.minY + box.maxY);
        const float hx = 0.5f * (box.maxX - box.minX);
        const float hy = 0.5f * (box.maxY - box.minY);
        const float separation =
            std::fabs(m_vx * (m_p1.x - cx) + m_vy * (m_p1.y - cy)) - (m_absVx * hx + m_absVy * hy);
        return !(separation > 0.0f);
    }

    /// Bounding box of the searched part of the segment.
    const Box& Bounds() const { return m_bounds; }
    float MaxFraction() const { return m_maxFraction; }

private:
    Vec2 m_p1;
    float m_dx, m_dy;
    float m_vx, m_vy, m_absVx, m_absVy;
    float m_maxFraction = 1.0f;
    Box m_bounds{};
};

} // namespace quadphase
