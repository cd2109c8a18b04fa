// SPDX-License-Identifier: MIT
// QuadtreeBroadPhase's proxies and settings: create, destroy, read, shift, configure and the task system. The other jobs have a file
// each: quadtree_move_queue.cpp, quadtree_pairs.cpp, quadtree_queries.cpp, quadtree_tuning.cpp, quadtree_checks.cpp.
#include "quadtree_broad_phase.h"

#include <cstring>
#include <new>
#include <stdexcept>
#include <string>

#include "quadtree_clock.h"
#include "report_error.h"

namespace quadphase
{
using detail::Clock;
using detail::SecondsSince;

namespace
{

bool SameBits(float a, float b)
{
    return std::memcmp(&a, &b, sizeof a) == 0;
}

// Whether the pyramid's layout (its bounds and depth, hence the order in which a query visits proxies, hence the
// pair order) depends on anything that differs between the two settings. The executor's settings (threads,
// executor, schedule, chunk, thresholds, task system) never change pairs or their order, so changing only them must not
// rebuild either: a rebuild re-tunes for the proxies of that moment and changes the layout from then on.
bool LayoutSettingsDiffer(const Config& a, const Config& b)
{
    return a.depth != b.depth || a.maxDepth != b.maxDepth || a.autoBounds != b.autoBounds ||
           !SameBits(a.cellToProxyRatio, b.cellToProxyRatio) || !SameBits(a.bounds.minX, b.bounds.minX) ||
           !SameBits(a.bounds.minY, b.bounds.minY) || !SameBits(a.bounds.maxX, b.bounds.maxX) ||
           !SameBits(a.bounds.maxY, b.bounds.maxY);
}

// A task system is all or nothing: a half-set one would silently run serially, or call a null pointer.
void CheckTaskSystem(const TaskSystem& tasks)
{
    const bool any = tasks.enqueueTask != nullptr || tasks.finishTask != nullptr;
    if (any && (tasks.enqueueTask == nullptr || tasks.finishTask == nullptr || tasks.workerCount < 1))
    {
        throw std::invalid_argument(
            "quadphase::Config::taskSystem: set enqueueTask, finishTask and workerCount >= 1 "
            "together, or none of them (got enqueueTask " +
            std::string(tasks.enqueueTask ? "set" : "null") + ", finishTask " +
            std::string(tasks.finishTask ? "set" : "null") + ", workerCount " +
            std::to_string(tasks.workerCount) + ")");
    }
}

// Reports non-finite and inverted boxes. The box is stored anyway: Pyramid places any box somewhere (NaN maps to
// cell 0), and Overlaps answers false for NaN, so a corrupted proxy gets no pairs and the others keep theirs.
QUADPHASE_NOINLINE void ReportBadBox(const Box& b, const char* call, ProxyId id)
{
    if (!IsFinite(b))
    {
        ReportError(ErrorCode::NonFiniteBox, "%s: proxy %d got box (%g, %g)-(%g, %g)", call, int(id),
                    double(b.minX), double(b.minY), double(b.maxX), double(b.maxY));
    }
    else if (!IsOrdered(b))
    {
        ReportError(ErrorCode::InvertedBox, "%s: proxy %d got box (%g, %g)-(%g, %g) with min > max", call,
                    int(id), double(b.minX), double(b.minY), double(b.maxX), double(b.maxY));
    }
}

const Box kEmptyBox{0.0f, 0.0f, 0.0f, 0.0f};

} // namespace

void QuadtreeBroadPhase::CheckBox(const Box& b, const char* call, ProxyId id)
{
    // Once per proxy: a runaway body gets a bad box at every step, and one line says all there is to say.
    if (!IsSane(b) && m_pool.MarkBadReported(id))
    {
        ReportBadBox(b, call, id);
    }
}

QuadtreeBroadPhase::QuadtreeBroadPhase(const FatPolicy& policy, const Config& config)
    : m_policy(policy), m_config(config)
{
    CheckTaskSystem(config.taskSystem);
    Retune();
    StartTeamIfDue();
}

ProxyId QuadtreeBroadPhase::CreateProxy(const Box& tight, void* userData)
{
    ApplyQueuedIfAny(); // a re-tune below reads every fat box
    const Clock::time_point start = m_timing ? Clock::now() : Clock::time_point{};
    const Box fat = FattenNew(m_policy, tight);
    ++m_mutations;
    // std::bad_alloc leaves no trace: the pool, the pyramid and the move buffer each reserve before they change,
    // and what succeeded is undone (without allocating) when a later step throws.
    m_pool.ReserveFree();
    const ProxyId id = m_pool.Allocate(fat, userData);
    try
    {
        m_pyramid.Insert(id, fat);
        try
        {
            m_pool.Buffer(id);
        }
        catch (...)
        {
            m_pyramid.Remove(id);
            throw;
        }
    }
    catch (...)
    {
        m_pool.Free(id);
        throw;
    }
    CheckBox(tight, "CreateProxy", id);
    if (m_pool.LiveCount() >= 2 * m_tunedCount && (m_config.depth < 0 || m_config.autoBounds))
    {
        // Re-tune while a scene is being built, so queries made before the first step are not all in one cell.
        // Doubling keeps the total rebuild work linear in the number of creations. The proxy exists from here:
        // a re-tune that runs out of memory is skipped (it is an optimisation; the next creation tries again).
        try
        {
            Retune();
        }
        catch (const std::bad_alloc&)
        {
        }
    }
    StartTeamIfDue();
    if (m_timing)
    {
        m_counters.updateSeconds += SecondsSince(start);
    }
    return id;
}

void QuadtreeBroadPhase::DestroyProxy(ProxyId id)
{
    if (!m_pool.CheckLive(id, "DestroyProxy"))
    {
        return;
    }
    ApplyQueuedIfAny(); // the id may be reused by the next CreateProxy: no queued move may outlive its proxy
    const Clock::time_point start = m_timing ? Clock::now() : Clock::time_point{};
    ++m_mutations;
    m_pool.ReserveFree(); // the only allocation, before any change
    m_pyramid.Remove(id);
    m_pool.Free(id);
    if (m_timing)
    {
        m_counters.updateSeconds += SecondsSince(start);
    }
}

const Box& QuadtreeBroadPhase::GetFatBox(ProxyId id) const
{
    ApplyQueuedIfAny();
    return m_pool.CheckLive(id, "GetFatAABB") ? m_pool.Fat(id) : kEmptyBox;
}

void* QuadtreeBroadPhase::GetUserData(ProxyId id) const
{
    return m_pool.IsLive(id) ? m_pool.UserData(id) : nullptr;
}

bool QuadtreeBroadPhase::TestOverlap(ProxyId a, ProxyId b) const
{
    if (!m_pool.CheckLive(a, "TestOverlap") || !m_pool.CheckLive(b, "TestOverlap"))
    {
        return false;
    }
    ApplyQueuedIfAny();
    return Overlaps(m_pool.Fat(a), m_pool.Fat(b));
}

void QuadtreeBroadPhase::ShiftOrigin(Vec2 newOrigin)
{
    ApplyQueuedIfAny(); // queued boxes are in the old frame
    // The world moved, so the region it lives in moves with it. The shifted pyramid is built first (the only
    // step that allocates), then everything is shifted: std::bad_alloc leaves the old frame intact.
    const Box bounds = m_pyramid.Bounds();
    Pyramid built = BuildPyramid(bounds.minX - newOrigin.x, bounds.minY - newOrigin.y,
                                 bounds.maxX - bounds.minX, m_pyramid.Depth(), newOrigin);
    // the same subtraction as BuildPyramid's, so entries and pool agree bit for bit
    m_pool.ShiftOrigin(newOrigin);
    WriteMirrorOfAll();
    m_config.bounds.minX -= newOrigin.x;
    m_config.bounds.minY -= newOrigin.y;
    m_config.bounds.maxX -= newOrigin.x;
    m_config.bounds.maxY -= newOrigin.y;
    CommitRebuild(std::move(built));
}

void QuadtreeBroadPhase::SetBoxMirror(const BoxMirror& mirror)
{
    ApplyQueuedIfAny(); // the records must hold the fat boxes the calls made so far define
    m_mirror = mirror;
    WriteMirrorOfAll();
}

void QuadtreeBroadPhase::WriteMirrorOfAll()
{
    if (!m_mirror.Enabled())
    {
        return;
    }
    for (ProxyId id = 0; id < m_pool.IdBound(); ++id)
    {
        if (m_pool.IsLive(id))
        {
            m_mirror.Write(id, m_pool.Fat(id));
        }
    }
}

void QuadtreeBroadPhase::Configure(const Config& config)
{
    CheckTaskSystem(config.taskSystem);
    // What one executor's parallel calls cost says nothing of another's: the measured choice starts afresh.
    const bool otherExecutor = config.executor != m_config.executor ||
                               config.taskSystem.enqueueTask != m_config.taskSystem.enqueueTask ||
                               config.taskSystem.userContext != m_config.taskSystem.userContext;
    if (!LayoutSettingsDiffer(m_config, config))
    {
        m_config = config;
    }
    else
    {
        ApplyQueuedIfAny();
        const Config previous = m_config;
        m_config = config;
        try
        {
            Retune();
        }
        catch (...)
        {
            m_config = previous; // all or nothing
            throw;
        }
    }
    if (otherExecutor)
    {
        m_choice = ThreadChoice{};
        m_aftermathSeconds = 0.0;
    }
    m_teamStarted = false; // the thread count or the executor may have changed
    StartTeamIfDue();
}

void QuadtreeBroadPhase::SetTaskSystem(const TaskSystem& tasks)
{
    CheckTaskSystem(tasks);
    m_config.taskSystem = tasks;
    m_choice = ThreadChoice{}; // what the executor's threads cost says nothing of the game's workers
    m_aftermathSeconds = 0.0;
    m_teamStarted = false;
    StartTeamIfDue();
}

} // namespace quadphase
