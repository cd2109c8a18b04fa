// SPDX-License-Identifier: MIT
// ThreadChoice (Config::threads == 0) driven by synthetic costs: which mode it settles on, how it probes, and that
// each mode is charged the aftermath of its own calls (the window of a call includes the cost the previous call's
// mode left behind).
#include <cstdint>
#include <vector>

#include <catch2/catch.hpp>

#include "thread_choice.h"

using quadphase::ThreadChoice;

namespace
{

/// Costs per unit of work of a call in each mode, and what a call in each mode adds to the next call's window.
struct Costs
{
    double serial = 100.0;
    double parallel = 60.0;
    double afterSerial = 0.0;
    double afterParallel = 0.0;
};

/// Runs `calls` eligible calls against `costs` (1000 units of work each) and returns the mode of each call.
std::vector<bool> Drive(ThreadChoice& choice, const Costs& costs, int calls)
{
    std::vector<bool> modes;
    bool previousParallel = false;
    bool first = true;
    for (int i = 0; i < calls; ++i)
    {
        const bool parallel = choice.Next();
        const double aftermath = first ? 0.0 : (previousParallel ? costs.afterParallel : costs.afterSerial);
        const double ns = (parallel ? costs.parallel : costs.serial) + aftermath;
        choice.Record(parallel, ns * 1000.0 * 1e-9, 1000.0);
        modes.push_back(parallel);
        previousParallel = parallel;
        first = false;
    }
    return modes;
}

int CountParallel(const std::vector<bool>& modes, size_t from)
{
    int n = 0;
    for (size_t i = from; i < modes.size(); ++i)
    {
        n += modes[i] ? 1 : 0;
    }
    return n;
}

} // namespace

TEST_CASE("ThreadChoice measures serial first, then parallel, and keeps the cheaper one", "[threads]")
{
    ThreadChoice choice;
    const std::vector<bool> modes = Drive(choice, Costs{}, 2000);
    // Serial first (two calls: the first pays no window of its own mode), then parallel.
    CHECK_FALSE(modes[0]);
    CHECK_FALSE(modes[1]);
    CHECK(modes[2]);
    CHECK(choice.Parallel());
    CHECK(choice.SerialNs() == Approx(100.0));
    CHECK(choice.ParallelNs() == Approx(60.0));
    // Probes of serial, three calls in a row, ever more rarely: the interval doubled up to its cap.
    CHECK(choice.ProbeEvery() == 1024);
    const int serialCalls = int(modes.size()) - CountParallel(modes, 0);
    CHECK(serialCalls < 60);
    CHECK(serialCalls % ThreadChoice::kProbeCalls == 2); // two initial calls, then whole probes
}

TEST_CASE("ThreadChoice needs parallel under the margin of serial", "[threads]")
{
    Costs costs;
    costs.parallel = 0.9 * costs.serial; // faster, but not by the margin
    ThreadChoice choice;
    const std::vector<bool> modes = Drive(choice, costs, 1000);
    CHECK_FALSE(choice.Parallel());
    CHECK(CountParallel(modes, 100) < 60);
}

TEST_CASE("ThreadChoice charges each mode the aftermath of its own calls", "[threads]")
{
    // Parallel calls are faster by themselves (60 against 100) but leave 70 behind for the next window: over a
    // step, parallel costs 130. A choice that timed the calls alone would keep parallel.
    Costs costs;
    costs.afterParallel = 70.0;
    ThreadChoice choice;
    const std::vector<bool> modes = Drive(choice, costs, 2000);
    CHECK_FALSE(choice.Parallel());
    CHECK(choice.ParallelNs() == Approx(130.0));
    CHECK(choice.SerialNs() == Approx(100.0));
    CHECK(CountParallel(modes, 100) < 60);

    // The other way round: serial leaves the cost behind, parallel is then the cheaper mode over a step even where
    // its calls alone are not under the margin.
    Costs reverse;
    reverse.parallel = 95.0;
    reverse.afterSerial = 40.0;
    ThreadChoice other;
    const std::vector<bool> otherModes = Drive(other, reverse, 2000);
    CHECK(other.Parallel());
    CHECK(other.SerialNs() == Approx(140.0));
    CHECK(CountParallel(otherModes, 100) > 1800);
}

TEST_CASE("ThreadChoice leaves a mode whose cost rose at once, and probes it only rarely after", "[threads]")
{
    ThreadChoice choice;
    Drive(choice, Costs{}, 300); // parallel preferred, probe interval grown
    REQUIRE(choice.Parallel());
    const int64_t interval = choice.ProbeEvery();
    REQUIRE(interval > 32);
    Costs busy; // the other core got busy: parallel regions now wait for it
    busy.parallel = 1000.0;
    const std::vector<bool> modes = Drive(choice, busy, int(2 * interval + 64));
    CHECK_FALSE(choice.Parallel());
    // Once it switched, it stays serial apart from probes.
    size_t switched = 0;
    while (switched < modes.size() && modes[switched])
    {
        ++switched;
    }
    REQUIRE(switched < size_t(interval) + 8);
    CHECK(CountParallel(modes, switched) <= 2 * ThreadChoice::kProbeCalls);
}

TEST_CASE("ThreadChoice probes a parallel mode that costs a hitch only at the longest interval", "[threads]")
{
    // Parallel regions that wait for a worker without a core: five times serial. Two initial parallel calls
    // measure it, one probe at the first interval confirms it, then none until the longest interval has passed
    // (doubling from 32 would probe five times in these calls, each probe a hitch).
    Costs busy;
    busy.parallel = 5.0 * busy.serial;
    ThreadChoice choice;
    const std::vector<bool> modes = Drive(choice, busy, 1100);
    CHECK_FALSE(choice.Parallel());
    CHECK(choice.ProbeEvery() == 1024);
    CHECK(CountParallel(modes, 0) <= 2 + 2 * ThreadChoice::kProbeCalls);

    // A parallel mode that merely loses (1.5x serial) is probed as before, doubling the interval.
    Costs losing;
    losing.parallel = 1.5 * losing.serial;
    ThreadChoice other;
    const std::vector<bool> otherModes = Drive(other, losing, 1100);
    CHECK_FALSE(other.Parallel());
    CHECK(CountParallel(otherModes, 0) > 2 + 3 * ThreadChoice::kProbeCalls);
}
