// SPDX-License-Identifier: MIT
// BruteForceBroadPhase: every buffered proxy tested against every live one.
#include "brute_force_broad_phase.h"

#include "quadphase/error.h"

namespace quadphase
{
namespace
{
const Box kEmptyBox{0.0f, 0.0f, 0.0f, 0.0f};
} // namespace

BruteForceBroadPhase::BruteForceBroadPhase(const FatPolicy& policy) : m_policy(policy) {}

ProxyId BruteForceBroadPhase::CreateProxy(const Box& tight, void* userData)
{
    const ProxyId id = m_pool.Allocate(FattenNew(m_policy, tight), userData);
    m_pool.Buffer(id);
    return id;
}

void BruteForceBroadPhase::DestroyProxy(ProxyId id)
{
    if (m_pool.CheckLive(id, "DestroyProxy"))
    {
        m_pool.Free(id);
    }
}

bool BruteForceBroadPhase::MoveProxy(ProxyId id, const Box& tight, Vec2 displacement)
{
    if (!m_pool.CheckLive(id, "MoveProxy") || !Refatten(m_policy, m_pool.Fat(id), tight, displacement))
    {
        return false;
    }
    m_pool.Buffer(id);
    return true;
}

void BruteForceBroadPhase::TouchProxy(ProxyId id)
{
    if (m_pool.CheckLive(id, "TouchProxy"))
    {
        m_pool.Buffer(id);
    }
}

void BruteForceBroadPhase::FindPairs(std::vector<Pair>& out)
{
    m_pool.LendBuffer(m_work);
    const size_t before = out.size();
    try
    {
        for (ProxyId q : m_work)
        {
            for (ProxyId p = 0; p < m_pool.IdBound(); ++p)
            {
                if (p == q || !m_pool.IsLive(p) || (p > q && m_pool.InWork(p)))
                {
                    continue;
                }
                if (Overlaps(m_pool.Fat(p), m_pool.Fat(q)))
                {
                    out.push_back(p < q ? Pair{p, q} : Pair{q, p});
                }
            }
        }
    }
    catch (...)
    {
        out.resize(before); // std::bad_alloc: nothing reported, nothing lost
        m_pool.RestoreBuffer(m_work);
        throw;
    }
    m_pool.ReturnBuffer(m_work);
}

void BruteForceBroadPhase::Query(const Box& box, QueryFn fn, void* context) const
{
    for (ProxyId p = 0; p < m_pool.IdBound(); ++p)
    {
        if (m_pool.IsLive(p) && Overlaps(m_pool.Fat(p), box) && !fn(context, p))
        {
            return;
        }
    }
}

void BruteForceBroadPhase::RayCast(const RayInput& input, RayCastFn fn, void* context) const
{
    SegmentTest segment(input);
    for (ProxyId p = 0; p < m_pool.IdBound(); ++p)
    {
        if (!m_pool.IsLive(p) || !segment.MayCross(m_pool.Fat(p)))
        {
            continue;
        }
        const float value = fn(context, RayInput{input.p1, input.p2, segment.MaxFraction()}, p);
        if (value == 0.0f)
        {
            return;
        }
        if (value > 0.0f)
        {
            segment.Clip(value);
        }
    }
}

void BruteForceBroadPhase::ShiftOrigin(Vec2 newOrigin)
{
    m_pool.ShiftOrigin(newOrigin);
}

const Box& BruteForceBroadPhase::GetFatBox(ProxyId id) const
{
    return m_pool.CheckLive(id, "GetFatAABB") ? m_pool.Fat(id) : kEmptyBox;
}

void* BruteForceBroadPhase::GetUserData(ProxyId id) const
{
    return m_pool.IsLive(id) ? m_pool.UserData(id) : nullptr;
}

} // namespace quadphase
