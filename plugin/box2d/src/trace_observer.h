// SPDX-License-Identifier: MIT
// Trace recording (quadphase::SetTrace): every call of a b2BroadPhase, appended to a caller's Trace.
#pragma once

#include <memory>

#include "broad_phase_observer.h"
#include "trace.h"

namespace quadphase
{
namespace detail
{

/// Records each call into `trace` as a TraceOp, with the core's ids and the boxes as the caller gave them (tight),
/// so that a replay through any broadphase makes the same calls. `trace` must outlive it.
std::unique_ptr<BroadPhaseObserver> NewTraceObserver(Trace& trace);

} // namespace detail
} // namespace quadphase
