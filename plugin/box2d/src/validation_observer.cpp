// SPDX-License-Identifier: MIT
// Validation mode: see validation_observer.h.
#include "validation_observer.h"

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <mutex>

#include "validation_log.h"

namespace quadphase
{
namespace detail
{
namespace
{

// The totals of every validator of the process.
std::atomic<int64_t> g_checks{0};
std::atomic<int64_t> g_mismatches{0};
std::once_flag g_summaryAtExit;

void PrintSummary()
{
    std::fprintf(stderr, "quadphase: validation: %lld UpdatePairs checked, %lld mismatches\n",
                 static_cast<long long>(g_checks.load()), static_cast<long long>(g_mismatches.load()));
    LogValidationTotals(g_checks.load(), g_mismatches.load(), true);
}

class ValidationObserver final : public BroadPhaseObserver
{
public:
    explicit ValidationObserver(const QuadtreeBroadPhase& core) : m_core(core), m_shadow(core)
    {
        std::call_once(g_summaryAtExit, [] { std::atexit(&PrintSummary); });
    }

    const ValidationReport& Report() const { return m_shadow.Report(); }

    void OnCreate(ProxyId id, const b2AABB& aabb, void*) override
    {
        m_shadow.OnCreate(id, aabb);
        AddToTotals();
    }
    void OnDestroy(ProxyId id) override
    {
        if (IsLive(id))
        {
            m_shadow.OnDestroy(id);
        }
    }
    void OnMove(ProxyId id, const b2AABB& aabb, const b2Vec2& displacement) override
    {
        if (IsLive(id))
        {
            m_shadow.OnMove(id, aabb, displacement);
        }
    }
    void OnTouch(ProxyId id) override
    {
        if (IsLive(id))
        {
            m_shadow.OnTouch(id);
        }
    }
    void OnUpdatePairs(const std::vector<Pair>& pairs) override
    {
        m_shadow.OnUpdatePairs(pairs);
        AddToTotals();
    }
    void OnShiftOrigin(const b2Vec2& newOrigin) override { m_shadow.OnShiftOrigin(newOrigin); }

private:
    bool IsLive(ProxyId id) const { return m_core.GetPool().IsLive(id); }

    void AddToTotals()
    {
        const ValidationReport& report = m_shadow.Report();
        const int64_t checks = g_checks += report.checks - m_addedChecks;
        const int64_t mismatches = g_mismatches += report.mismatches - m_addedMismatches;
        if (report.checks != m_addedChecks || report.mismatches != m_addedMismatches)
        {
            LogValidationTotals(checks, mismatches, false);
        }
        m_addedChecks = report.checks;
        m_addedMismatches = report.mismatches;
    }

    const QuadtreeBroadPhase& m_core;
    ShadowValidator m_shadow;
    // the part of m_shadow's report already in the process-wide totals
    int64_t m_addedChecks = 0;
    int64_t m_addedMismatches = 0;
};

} // namespace

std::unique_ptr<BroadPhaseObserver> NewValidationObserver(const QuadtreeBroadPhase& core)
{
    return std::unique_ptr<BroadPhaseObserver>(new ValidationObserver(core));
}

const ValidationReport& ValidationReportOf(const BroadPhaseObserver& validation)
{
    return static_cast<const ValidationObserver&>(validation).Report();
}

} // namespace detail
} // namespace quadphase
