// SPDX-License-Identifier: MIT
// qp-replay's engine over a quadphase::BroadPhaseInterface implementation (replay_loop.h's Engine concept),
// with the buffered-proxy tracking the quadtree's checking run uses; the one checking-then-timed run path every
// engine goes through (Contender, Drive); and the entry point of the other engines (replay_peers.cpp lists them
// and their two modes).
#pragma once

#include <functional>
#include <string>
#include <type_traits>
#include <vector>

#include "box_simd.h"
#include "loaded_trace.h"
#include "pair_hash.h"
#include "quadtree_broad_phase.h"
#include "timed_run.h"

namespace qpbench
{

using quadphase::ProxyId;

/// An engine behind quadphase::BroadPhaseInterface: QuadtreeBroadPhase, BruteForceBroadPhase, the paper's
/// design (the calls below are direct: the classes, or BruteForceBroadPhase's proxy calls, are final).
template <typename BP>
class CoreEngine
{
public:
    template <typename... A>
    explicit CoreEngine(A&&... a) : m_bp(std::forward<A>(a)...)
    {
    }

    int32_t Create(const Box& tight, int32_t recorded)
    {
        const ProxyId id = m_bp.CreateProxy(tight, reinterpret_cast<void*>(intptr_t(recorded)));
        if (m_track)
        {
            Mark(id);
        }
        return id;
    }
    void Destroy(int32_t id) { m_bp.DestroyProxy(id); }
    void Move(int32_t id, const Box& tight, Vec2 d)
    {
        if constexpr (std::is_same_v<BP, quadphase::QuadtreeBroadPhase>)
        {
            if (!m_track)
            {
                // As b2BroadPhase::MoveProxy does it: the fat-box test at the call, against the proxy's current fat
                // box (the pool holds it: the queue holds only moves whose box is already there), and the id queued
                // when the box changed (QueueFatMove); the cells' upkeep waits for FindPairs. A bad box goes to
                // QueueMove, which reports it, as the adapter's slow path does.
                Box fat;
                bool sane;
                if (quadphase::KeptAndSaneSimd(m_bp.GetPolicy(), m_bp.GetPool().Fat(id), &tight.minX,
                                               &tight.maxX, d, fat, sane))
                {
                    return;
                }
                if (sane)
                {
                    m_bp.QueueFatMove(id, tight, fat);
                }
                else
                {
                    m_bp.QueueMove(id, tight, d);
                }
                return;
            }
        }
        const bool buffered = m_bp.MoveProxy(id, tight, d);
        if (m_track && buffered)
        {
            Mark(id);
        }
    }
    void Touch(int32_t id)
    {
        m_bp.TouchProxy(id);
        if (m_track)
        {
            Mark(id);
        }
    }
    void UpdatePairs()
    {
        m_pairs.clear();
        m_bp.FindPairs(m_pairs);
    }
    void ShiftOrigin(Vec2 o) { m_bp.ShiftOrigin(o); }
    int32_t ProxyCount() const { return m_bp.GetProxyCount(); }
    size_t PairCount() const { return m_pairs.size(); }
    void PairKeys(std::vector<uint64_t>& keys) const
    {
        for (const quadphase::Pair& p : m_pairs)
        {
            keys.push_back(
                PairKey(int32_t(intptr_t(m_bp.GetUserData(p.a))), int32_t(intptr_t(m_bp.GetUserData(p.b)))));
        }
    }
    void BeginTimedSteps()
    {
        if constexpr (std::is_same_v<BP, quadphase::QuadtreeBroadPhase>)
        {
            m_bp.ResetCounters();
        }
    }

    BP& Get() { return m_bp; }

    // Buffered-proxy tracking for the checking run: the live proxies that the next UpdatePairs will query.
    void SetTracking(bool on) { m_track = on; }
    /// QuadtreeBroadPhase only (the pool says which buffered proxies are still live).
    std::vector<ProxyId> TakeBuffered()
    {
        std::vector<ProxyId> live;
        for (ProxyId id : m_buffered)
        {
            m_flag[size_t(id)] = 0;
            if (m_bp.GetPool().IsLive(id))
            {
                live.push_back(id);
            }
        }
        m_buffered.clear();
        return live;
    }

private:
    void Mark(ProxyId id)
    {
        if (size_t(id) >= m_flag.size())
        {
            m_flag.resize(size_t(id) * 2 + 16, 0);
        }
        if (!m_flag[size_t(id)])
        {
            m_flag[size_t(id)] = 1;
            m_buffered.push_back(id);
        }
    }

    BP m_bp;
    std::vector<quadphase::Pair> m_pairs;
    bool m_track = false;
    std::vector<uint8_t> m_flag;
    std::vector<ProxyId> m_buffered;
};

/// One engine configuration of a run: its timings (named for the printed lines), its untimed checking run
/// (empty: none; it appends its JSON line and returns its mismatching UpdatePairs calls) and one timed run.
struct Contender
{
    Timings timings;
    std::function<int64_t()> check;
    std::function<void(Timings&)> timed;
};

/// The run of every engine: the checking runs of the first `checked` contenders, then `repeats` rounds of one
/// timed run of each (in order within each round, so slow phases of a noisy machine hit every contender alike),
/// then the medians. Exits with 3 after a mismatch.
inline void Drive(std::vector<Contender>& contenders, size_t checked, int repeats)
{
    int64_t mismatches = 0;
    for (size_t i = 0; i < std::min(checked, contenders.size()); ++i)
    {
        mismatches += contenders[i].check ? contenders[i].check() : 0;
    }
    for (int r = 0; r < repeats; ++r)
    {
        for (Contender& c : contenders)
        {
            c.timed(c.timings);
        }
    }
    for (const Contender& c : contenders)
    {
        c.timings.PrintMedians();
    }
    if (mismatches != 0)
    {
        Die(3, "qp-replay: %lld MISMATCHING UpdatePairs calls\n", static_cast<long long>(mismatches));
    }
}

/// What a peer's run needs: the options (--hashes-out, --compare-hashes, --levels, --threads, ...), the trace,
/// the --engine name and a JSON line with the common fields (kind: "run", "check").
struct PeerRun
{
    const Args& args;
    const LoadedTrace& loaded;
    std::string engine;
    std::function<JsonLine(const char*)> base;
};

/// Brute force (--engine brute, or --brute beside the quadtree) is refused above --max-proxies (default 20000),
/// where it would take too long: exits with 2.
inline void RefuseLargeBrute(const Args& args, const LoadedTrace& loaded)
{
    const long maxProxies = args.GetInt("max-proxies", 20000);
    if (loaded.steps.proxies > maxProxies)
    {
        Die(2, "qp-replay: brute force on %lld proxies (> --max-proxies %ld) refused\n",
            static_cast<long long>(loaded.steps.proxies), maxProxies);
    }
}

/// `run.engine` as a contender (its check and timed runs refer to `run`, which must outlive it). Exits with 2
/// on an engine that is unknown or not built here, or refused settings.
Contender PeerContender(const PeerRun& run);

} // namespace qpbench
