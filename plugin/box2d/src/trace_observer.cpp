// SPDX-License-Identifier: MIT
// Trace recording: see trace_observer.h.
#include "trace_observer.h"

#include "box2d_types.h"

namespace quadphase
{
namespace detail
{
namespace
{

class TraceObserver final : public BroadPhaseObserver
{
public:
    explicit TraceObserver(Trace& trace) : m_trace(trace) {}

    void OnCreate(ProxyId id, const b2AABB& aabb, void*) override
    {
        m_trace.Add({TraceOp::Create, id, ToBox(aabb), {}});
    }
    void OnDestroy(ProxyId id) override { m_trace.Add({TraceOp::Destroy, id, {}, {}}); }
    void OnMove(ProxyId id, const b2AABB& aabb, const b2Vec2& displacement) override
    {
        m_trace.Add({TraceOp::Move, id, ToBox(aabb), {displacement.x, displacement.y}});
    }
    void OnTouch(ProxyId id) override { m_trace.Add({TraceOp::Touch, id, {}, {}}); }
    void OnUpdatePairs(const std::vector<Pair>&) override { m_trace.Add({TraceOp::UpdatePairs, -1, {}, {}}); }
    void OnShiftOrigin(const b2Vec2& newOrigin) override
    {
        m_trace.Add({TraceOp::ShiftOrigin, -1, {}, {newOrigin.x, newOrigin.y}});
    }

private:
    Trace& m_trace;
};

} // namespace

std::unique_ptr<BroadPhaseObserver> NewTraceObserver(Trace& trace)
{
    return std::unique_ptr<BroadPhaseObserver>(new TraceObserver(trace));
}

} // namespace detail
} // namespace quadphase
