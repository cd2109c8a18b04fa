// SPDX-License-Identifier: MIT
// ShadowValidator: a b2DynamicTree fed the same calls as the quadtree, compared with it at every UpdatePairs.
#include "shadow_validator.h"

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdint>
#include <cstdio>

#include "report_error.h"
#include "validation_log.h"

namespace quadphase
{
namespace
{

// A coordinate t with fl(t - r) == target (sign -1) or fl(t + r) == target (sign +1), so that a proxy created in
// the shadow tree from t gets exactly the fat coordinate the quadtree stores. Float subtraction is monotone, so a
// short walk from the first guess finds it when it exists.
bool Preimage(float target, float r, float sign, float& t)
{
    t = target - sign * r;
    for (int i = 0; i < 64; ++i)
    {
        const float v = t + sign * r;
        if (v == target)
        {
            return true;
        }
        t = std::nextafter(t, v < target ? INFINITY : -INFINITY);
    }
    return false;
}

std::string BoxText(const b2AABB& b)
{
    char text[160];
    std::snprintf(text, sizeof(text), "(%.9g, %.9g)-(%.9g, %.9g)", double(b.lowerBound.x),
                  double(b.lowerBound.y), double(b.upperBound.x), double(b.upperBound.y));
    return text;
}

b2AABB ToAABB(const Box& b)
{
    b2AABB a;
    a.lowerBound.Set(b.minX, b.minY);
    a.upperBound.Set(b.maxX, b.maxY);
    return a;
}

} // namespace

ShadowValidator::ShadowValidator(const QuadtreeBroadPhase& core) : m_core(core)
{
    // Moves queued before validation starts must be in the fat boxes the shadow tree is seeded with: the shadow
    // never sees those MoveProxy calls, and the quadtree would apply them only at the next UpdatePairs (a false
    // "extra pair" then). Applied now, they put their proxies in the move buffer, so the check below skips that
    // first comparison, whose buffers differ.
    core.ApplyQueuedMoves();
    const ProxyPool& pool = core.GetPool();
    const float r = b2_aabbExtension;
    for (ProxyId id = 0; id < pool.IdBound(); ++id)
    {
        if (!pool.IsLive(id))
        {
            continue;
        }
        const Box& fat = pool.Fat(id);
        b2AABB tight;
        bool exact = Preimage(fat.minX, r, -1.0f, tight.lowerBound.x);
        exact = Preimage(fat.minY, r, -1.0f, tight.lowerBound.y) && exact;
        exact = Preimage(fat.maxX, r, 1.0f, tight.upperBound.x) && exact;
        exact = Preimage(fat.maxY, r, 1.0f, tight.upperBound.y) && exact;
        // A fat AABB that a move's displacement or ShiftOrigin produced may have no tight AABB that
        // b2DynamicTree::CreateProxy fattens to it (fl(t - 0.1) skips every other float below a power of two).
        // Such a proxy is seeded one float off and left out of the comparisons until a move gives both trees the
        // same bits again: not a mismatch, since the quadtree is right
        // (tests/fuzz/regressions/box2d/validation-midrun-inexact-seed).
        AddShadow(id, tight);
        SetInexact(id, !exact);
        if (exact)
        {
            CompareFat(id, "seed");
        }
    }
    // Proxies already waiting in the quadtree's move buffer are not in the shadow's; the buffers agree again after
    // the next UpdatePairs, so that one is not compared.
    if (pool.BufferedCount() > 0)
    {
        m_report.checks = -1;
    }
    m_buffer.clear();
}

void ShadowValidator::SetInexact(ProxyId id, bool inexact)
{
    if (size_t(id) >= m_inexact.size())
    {
        m_inexact.resize(size_t(id) + 1, 0);
    }
    m_inexact[size_t(id)] = inexact ? 1 : 0;
}

bool ShadowValidator::IsInexact(ProxyId id) const
{
    return id >= 0 && size_t(id) < m_inexact.size() && m_inexact[size_t(id)] != 0;
}

std::string ShadowValidator::Describe(ProxyId id) const
{
    if (!m_core.GetPool().IsLive(id))
    {
        return std::to_string(id) + " (destroyed)";
    }
    return std::to_string(id) + " fat AABB " + BoxText(ToAABB(m_core.GetPool().Fat(id)));
}

void ShadowValidator::Mismatch(const std::string& what)
{
    ++m_report.mismatches;
    if (m_report.firstMismatch.empty())
    {
        m_report.firstMismatch = what;
    }
    // QUADPHASE_VALIDATE_LOG: in the file before anything else can happen
    detail::LogValidationMismatch(what);
    ReportError(kValidationMismatch, "validation mismatch: %s", what.c_str());
}

void ShadowValidator::CompareFat(ProxyId id, const char* call)
{
    const b2AABB& shadow = m_tree.GetFatAABB(m_shadowOf[size_t(id)]);
    const Box& ours = m_core.GetPool().Fat(id);
    const bool same = SameBits(
        ours, Box{shadow.lowerBound.x, shadow.lowerBound.y, shadow.upperBound.x, shadow.upperBound.y});
    if (IsInexact(id))
    {
        if (same)
        {
            m_exactAgain.push_back(id); // compared again from the next UpdatePairs on
        }
        return;
    }
    if (!SameBits(ours,
                  Box{shadow.lowerBound.x, shadow.lowerBound.y, shadow.upperBound.x, shadow.upperBound.y}) &&
        IsFinite(ours))
    {
        Mismatch(std::string(call) + ": proxy " + Describe(id) + " but b2DynamicTree stores " +
                 BoxText(shadow));
    }
}

void ShadowValidator::AddShadow(ProxyId id, const b2AABB& aabb)
{
    if (size_t(id) >= m_shadowOf.size())
    {
        m_shadowOf.resize(size_t(id) + 1, -1);
    }
    m_shadowOf[size_t(id)] = m_tree.CreateProxy(aabb, reinterpret_cast<void*>(intptr_t(id)));
    m_buffer.push_back(id);
}

void ShadowValidator::OnCreate(ProxyId id, const b2AABB& aabb)
{
    AddShadow(id, aabb);
    SetInexact(id, false);
    CompareFat(id, "CreateProxy");
}

void ShadowValidator::OnDestroy(ProxyId id)
{
    std::replace(m_buffer.begin(), m_buffer.end(), id, ProxyId(-1));
    std::replace(m_moved.begin(), m_moved.end(), id, ProxyId(-1));
    m_tree.DestroyProxy(m_shadowOf[size_t(id)]);
    m_shadowOf[size_t(id)] = -1;
}

void ShadowValidator::OnMove(ProxyId id, const b2AABB& aabb, const b2Vec2& displacement)
{
    const bool moved = m_tree.MoveProxy(m_shadowOf[size_t(id)], aabb, displacement);
    if (moved)
    {
        m_buffer.push_back(id);
    }
    // The quadtree has only queued this move; its fat AABB is compared once UpdatePairs has applied it. A wrong
    // keep-or-refatten decision shows there as different bits.
    m_moved.push_back(id);
}

void ShadowValidator::OnTouch(ProxyId id)
{
    m_buffer.push_back(id);
}

void ShadowValidator::OnShiftOrigin(const b2Vec2& newOrigin)
{
    m_tree.ShiftOrigin(newOrigin);
}

bool ShadowValidator::QueryCallback(int32 shadowId)
{
    const ProxyId other = ProxyId(reinterpret_cast<intptr_t>(m_tree.GetUserData(shadowId)));
    if (other != m_queryId)
    {
        m_expected.push_back(other < m_queryId ? Pair{other, m_queryId} : Pair{m_queryId, other});
    }
    return true;
}

void ShadowValidator::OnUpdatePairs(const std::vector<Pair>& reported)
{
    for (ProxyId id : m_moved)
    {
        if (id >= 0)
        {
            CompareFat(id, "MoveProxy");
        }
    }
    m_moved.clear();
    // Stock semantics: for every buffered proxy, every other proxy whose fat AABB overlaps its own.
    m_expected.clear();
    for (ProxyId q : m_buffer)
    {
        if (q < 0)
        {
            continue;
        }
        m_queryId = q;
        m_tree.Query(this, m_tree.GetFatAABB(m_shadowOf[size_t(q)]));
    }
    m_buffer.clear();
    std::sort(m_expected.begin(), m_expected.end());
    m_expected.erase(std::unique(m_expected.begin(), m_expected.end()), m_expected.end());

    m_actual = reported;
    std::sort(m_actual.begin(), m_actual.end());
    const bool duplicates = std::adjacent_find(m_actual.begin(), m_actual.end()) != m_actual.end();
    // Pairs of a proxy seeded inexactly are not compared (see the constructor); the flags of those whose fat AABBs
    // agree again are cleared only now, since this call's move buffers were decided with the old bits.
    if (!m_inexact.empty())
    {
        const auto inexact = [this](const Pair& p) {
            return IsInexact(p.a) || IsInexact(p.b);
        };
        m_expected.erase(std::remove_if(m_expected.begin(), m_expected.end(), inexact), m_expected.end());
        m_actual.erase(std::remove_if(m_actual.begin(), m_actual.end(), inexact), m_actual.end());
    }
    for (ProxyId id : m_exactAgain)
    {
        SetInexact(id, false);
    }
    m_exactAgain.clear();

    if (++m_report.checks <= 0)
    {
        return; // the first UpdatePairs after validation started mid-run (see the constructor)
    }
    m_report.pairsCompared += int64_t(m_expected.size());
    if (duplicates)
    {
        Mismatch("UpdatePairs: the quadtree reported a pair twice");
    }
    if (m_actual != m_expected)
    {
        // First pair in one set and not the other.
        std::vector<Pair> missing, extra;
        std::set_difference(m_expected.begin(), m_expected.end(), m_actual.begin(), m_actual.end(),
                            std::back_inserter(missing));
        std::set_difference(m_actual.begin(), m_actual.end(), m_expected.begin(), m_expected.end(),
                            std::back_inserter(extra));
        const bool isMissing = !missing.empty();
        const Pair p = isMissing ? missing.front() : extra.front();
        char head[200];
        std::snprintf(head, sizeof(head),
                      "UpdatePairs #%" PRId64 ": %zu pairs missing, %zu extra; first %s pair: ",
                      m_report.checks, missing.size(), extra.size(), isMissing ? "missing" : "extra");
        Mismatch(std::string(head) + "proxy " + Describe(p.a) + " and proxy " + Describe(p.b));
    }
    if (m_report.checks % 64 == 0)
    {
        const std::string problem = m_core.Validate();
        if (!problem.empty())
        {
            Mismatch("quadtree invariant: " + problem);
        }
    }
}

} // namespace quadphase
