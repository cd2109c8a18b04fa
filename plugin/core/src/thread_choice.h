// SPDX-License-Identifier: MIT
// Serial or parallel: the choice Config::threads == 0 makes for each large FindPairs call, from measured costs.
#pragma once

#include <cstdint>

namespace quadphase
{

/// Chooses between a serial and a parallel FindPairs call from what each mode was measured to cost, per unit of
/// work, on recent calls. Only the time of a call depends on it, never the pairs or their order.
///
/// What a mode costs is measured over a *window*: the broadphase work since the previous eligible call ended (the
/// queued moves applied in between) plus the call itself. Why the window and not the call alone: a parallel call
/// leaves the data its second thread read (cell entries, fat boxes, flags) in that thread's cache, and the caller's
/// thread pays to take it back when it next writes it, while applying the next step's moves. Where a cache line
/// takes long to pass from one core to the other, parallel calls that are faster by themselves can be slower over
/// the step, and a choice that timed the calls alone would keep them parallel (docs/design.md, "Parallel pair
/// generation"). A window is credited to its call's mode only
/// when the previous eligible call ran in the same mode, so that each mode is charged its own aftermath.
///
/// Schedule: the preferred mode runs; every ProbeEvery() eligible calls the other one runs kProbeCalls times in a
/// row (the first of them only pays the other mode's aftermath, the rest are measured). A probe that leaves the
/// preference unchanged doubles the interval, up to 1024 calls; one that changes it resets the interval to 32; a
/// probe that finds parallel above kHarmfulRatio x serial sets it to 1024 at once.
/// Serial is measured first, then parallel, and parallel must be faster by a margin (kParallelMargin): a parallel
/// region whose second thread waits for a core that another program holds costs milliseconds where serial costs
/// tens of microseconds, so a wrong start on a busy machine is expensive.
///
/// Use: Next() before each eligible call, Record() after it, in the same order. Not thread-safe (FindPairs is not).
class ThreadChoice
{
public:
    static constexpr int kProbeCalls = 3;
    // parallel is preferred when under this fraction of serial
    static constexpr double kParallelMargin = 0.85;
    // parallel measured above this multiple of serial was a hitch, not a mere loss (see Record)
    static constexpr double kHarmfulRatio = 3.0;

    /// The mode of the next eligible call: true for parallel.
    bool Next()
    {
        ++m_calls;
        const int64_t phase = m_calls % m_probeEvery;
        if (!m_probing && phase == m_probeEvery - kProbeCalls)
        {
            m_probing = true;
            m_probeParallel = !Parallel();
        }
        return m_probing ? m_probeParallel : Parallel();
    }

    /// The call Next() announced has run in mode `parallel`; `seconds` is its window (see the class comment) and
    /// `work` its units of work (> 0).
    void Record(bool parallel, double seconds, double work)
    {
        const bool measured = m_calls > 1 && parallel == m_lastParallel;
        m_lastParallel = parallel;
        if (measured && work > 0.0)
        {
            const double ns = 1e9 * seconds / work;
            double& average = parallel ? m_parallelNs : m_serialNs;
            average = average == 0.0 ? ns : 0.75 * average + 0.25 * ns;
        }
        if (m_probing && m_calls % m_probeEvery == m_probeEvery - 1)
        {
            m_probing = false;
            // A probe that did not change the preference was wasted: probe less often. A probe of parallel that
            // found it above kHarmfulRatio x serial waited for a worker that had no core (a busy machine, or the
            // game's own threads on every core): each such probe is a hitch of a scheduler time slice in some step,
            // so the next one waits the longest interval at once (bench/results/frames.md, particles 20,000 beside
            // a busy thread). Only a whole probe decides it: one slow call on a quiet machine does not.
            const bool changed = Parallel() == m_probeParallel;
            const bool harmful = m_probeParallel && !changed && m_parallelNs > kHarmfulRatio * m_serialNs;
            m_probeEvery = changed ? 32 : (harmful || m_probeEvery >= 1024 ? 1024 : 2 * m_probeEvery);
        }
    }

    /// The preferred mode: serial until serial has been measured, then parallel until it has been, then the
    /// cheaper one (parallel only when under kParallelMargin of serial).
    bool Parallel() const
    {
        if (m_serialNs == 0.0)
        {
            return false;
        }
        return m_parallelNs == 0.0 || m_parallelNs < kParallelMargin * m_serialNs;
    }

    /// Moving averages of ns per unit of work (0: not measured yet), and the probe interval, for tests and stats.
    double SerialNs() const { return m_serialNs; }
    double ParallelNs() const { return m_parallelNs; }
    int64_t ProbeEvery() const { return m_probeEvery; }

private:
    double m_serialNs = 0.0;
    double m_parallelNs = 0.0;
    int64_t m_calls = 0; // eligible calls so far
    int64_t m_probeEvery = 32;
    bool m_probing = false;
    bool m_probeParallel = false;
    bool m_lastParallel = false; // mode of the previous eligible call
};

} // namespace quadphase
