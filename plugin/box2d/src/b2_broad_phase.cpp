// quadphase's b2BroadPhase: forwards Box2D's calls to the quadtree and, in validation mode, to a shadow tree.
#include "box2d/b2_broad_phase.h"

#include <cstdlib>
#include <cstring>

#include "quadphase/shadow_validator.h"

namespace
{

bool ValidationRequestedByEnvironment()
{
    const char* value = std::getenv("QUADPHASE_VALIDATE");
    return value != nullptr && value[0] != '\0' && std::strcmp(value, "0") != 0;
}

quadphase::FatPolicy Box2DFatPolicy()
{
    quadphase::FatPolicy policy;
    policy.extension = b2_aabbExtension;
    policy.multiplier = b2_aabbMultiplier;
    return policy;
}

} // namespace

b2BroadPhase::b2BroadPhase()
    : m_core(Box2DFatPolicy())
{
    if (ValidationRequestedByEnvironment())
    {
        SetValidation(true);
    }
}

b2BroadPhase::~b2BroadPhase()
{
    delete m_shadow;
}

void b2BroadPhase::SetValidation(bool enabled)
{
    if (enabled && m_shadow == nullptr)
    {
        m_shadow = new quadphase::ShadowValidator(m_core);
    }
    else if (!enabled)
    {
        delete m_shadow;
        m_shadow = nullptr;
    }
}

int32 b2BroadPhase::CreateProxy(const b2AABB& aabb, void* userData)
{
    const int32 proxyId = m_core.CreateProxy(quadphase::detail::ToBox(aabb), userData);
    if (m_trace != nullptr)
    {
        m_trace->Add({quadphase::TraceOp::Create, proxyId, quadphase::detail::ToBox(aabb), {}});
    }
    if (m_shadow != nullptr)
    {
        m_shadow->OnCreate(proxyId, aabb);
    }
    return proxyId;
}

void b2BroadPhase::DestroyProxy(int32 proxyId)
{
    if (m_trace != nullptr)
    {
        m_trace->Add({quadphase::TraceOp::Destroy, proxyId, {}, {}});
    }
    if (m_shadow != nullptr && m_core.GetPool().IsLive(proxyId))
    {
        m_shadow->OnDestroy(proxyId);
    }
    m_core.DestroyProxy(proxyId);
}

void b2BroadPhase::MoveProxy(int32 proxyId, const b2AABB& aabb, const b2Vec2& displacement)
{
    if (m_trace != nullptr)
    {
        m_trace->Add({quadphase::TraceOp::Move, proxyId, quadphase::detail::ToBox(aabb), {displacement.x, displacement.y}});
    }
    // Queued: Box2D moves its bodies one by one on this thread; the fat-AABB tests run in parallel in UpdatePairs.
    m_core.QueueMove(proxyId, quadphase::detail::ToBox(aabb), {displacement.x, displacement.y});
    if (m_shadow != nullptr && m_core.GetPool().IsLive(proxyId))
    {
        m_shadow->OnMove(proxyId, aabb, displacement);
    }
}

void b2BroadPhase::TouchProxy(int32 proxyId)
{
    if (m_trace != nullptr)
    {
        m_trace->Add({quadphase::TraceOp::Touch, proxyId, {}, {}});
    }
    m_core.TouchProxy(proxyId);
    if (m_shadow != nullptr && m_core.GetPool().IsLive(proxyId))
    {
        m_shadow->OnTouch(proxyId);
    }
}

const b2AABB& b2BroadPhase::GetFatAABB(int32 proxyId) const
{
    const quadphase::Box& box = m_core.GetFatBox(proxyId); // reports an unknown id and gives an empty box
    if (proxyId < 0)
    {
        static const b2AABB empty = {{0.0f, 0.0f}, {0.0f, 0.0f}};
        return empty;
    }
    std::lock_guard<std::mutex> lock(m_fatCopiesMutex);
    const size_t chunk = size_t(proxyId / kFatChunk);
    if (chunk >= m_fatCopies.size())
    {
        m_fatCopies.resize(chunk + 1);
    }
    if (!m_fatCopies[chunk])
    {
        m_fatCopies[chunk].reset(new b2AABB[kFatChunk]);
    }
    b2AABB& copy = m_fatCopies[chunk][proxyId % kFatChunk];
    copy.lowerBound.Set(box.minX, box.minY);
    copy.upperBound.Set(box.maxX, box.maxY);
    return copy;
}

void b2BroadPhase::CheckPairs()
{
    m_shadow->OnUpdatePairs(m_pairs);
}

int32 b2BroadPhase::GetTreeHeight() const
{
    return m_core.GetPyramid().Depth();
}

int32 b2BroadPhase::GetTreeBalance() const
{
    int64_t occupied = 0;
    int64_t largest = 0;
    m_core.GetPyramid().CountOccupancy(occupied, largest);
    return int32(largest);
}

float b2BroadPhase::GetTreeQuality() const
{
    int64_t occupied = 0;
    int64_t largest = 0;
    m_core.GetPyramid().CountOccupancy(occupied, largest);
    return occupied > 0 ? float(m_core.GetProxyCount()) / float(occupied) : 0.0f;
}

void b2BroadPhase::ShiftOrigin(const b2Vec2& newOrigin)
{
    if (m_trace != nullptr)
    {
        m_trace->Add({quadphase::TraceOp::ShiftOrigin, -1, {}, {newOrigin.x, newOrigin.y}});
    }
    m_core.ShiftOrigin({newOrigin.x, newOrigin.y});
    if (m_shadow != nullptr)
    {
        m_shadow->OnShiftOrigin(newOrigin);
    }
}
