// SPDX-License-Identifier: MIT
// Validation mode (quadphase::SetValidation, QUADPHASE_VALIDATE=1): a ShadowValidator fed every call of a
// b2BroadPhase, and the totals of every validating broadphase of the process, printed at exit.
#pragma once

#include <memory>

#include "broad_phase_observer.h"
#include "shadow_validator.h"

namespace quadphase
{
namespace detail
{

/// Starts validating `core` (see ShadowValidator's constructor): the shadow tree is fed the calls the core carried
/// out (every create, and the other calls on live proxies), and what it finds is added to the process-wide totals
/// as it goes. Once validation ran, the process prints
/// "quadphase: validation: N UpdatePairs checked, M mismatches" to stderr at exit, and with
/// QUADPHASE_VALIDATE_LOG it also appends the totals to that file as they grow (validation_log.h).
std::unique_ptr<BroadPhaseObserver> NewValidationObserver(const QuadtreeBroadPhase& core);

/// What the observer NewValidationObserver made has found so far.
const ValidationReport& ValidationReportOf(const BroadPhaseObserver& validation);

} // namespace detail
} // namespace quadphase
