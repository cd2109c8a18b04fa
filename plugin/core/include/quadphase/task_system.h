// SPDX-License-Identifier: MIT
// The game's own job system, handed to quadphase so that pair generation runs on the game's workers instead of
// OpenMP's threads. Modelled on Box2D v3's b2WorldDef (enqueueTask, finishTask, workerCount, userTaskContext).
#pragma once

namespace quadphase
{

/// One range of items of a task: run items [startIndex, endIndex) on worker `workerIndex` (< workerCount).
/// quadphase's task callbacks never throw.
using TaskCallback = void(int startIndex, int endIndex, unsigned workerIndex, void* taskContext);

/// Starts `task` over the items [0, itemCount): the game calls task(start, end, worker, taskContext) over ranges
/// that cover every item exactly once, each range at least `minRange` items long (the last one may be shorter),
/// from any of its workers and concurrently, with a workerIndex in [0, workerCount) that no other range running at
/// the same time has. It may also run every range itself before returning. Returns a handle for finishTask, or
/// nullptr when the task already ran to completion (finishTask is then not called).
using EnqueueTaskCallback = void*(TaskCallback* task, int itemCount, int minRange, void* taskContext,
                                  void* userContext);

/// Waits until every range of the task behind `userTask` has returned. The calling thread may help run them.
using FinishTaskCallback = void(void* userTask, void* userContext);

/// A game's job system. Set both callbacks and workerCount >= 1 to use it, or leave everything at its default
/// (Config::executor: the library's pool unless set otherwise). While it is set quadphase makes no OpenMP call and
/// starts no thread of its own; enqueueTask and finishTask are called only from the thread that calls FindPairs
/// (b2World::Step, b2BroadPhase::UpdatePairs). The pairs and their order do not depend on it, nor on the worker count
/// or the order in which ranges run.
struct TaskSystem
{
    EnqueueTaskCallback* enqueueTask = nullptr;
    FinishTaskCallback* finishTask = nullptr;
    /// How many workers may run ranges at once (the caller's thread counts if it helps): the team size quadphase
    /// plans for, as Config::threads would be for OpenMP.
    int workerCount = 0;
    /// Passed back to enqueueTask and finishTask untouched.
    void* userContext = nullptr;
};

} // namespace quadphase
