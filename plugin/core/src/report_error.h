// SPDX-License-Identifier: MIT
// How quadphase's own code reports bad input and misuse: through the handler a user installs with SetErrorHandler
// (quadphase/error.h). The core and the Box2D adapter call it; users do not.
#pragma once

#include "compiler.h"
#include "quadphase/error.h"

namespace quadphase
{

/// Reports an error through the installed handler. printf-style.
void ReportError(ErrorCode code, const char* format, ...) QUADPHASE_PRINTF_FORMAT(2, 3);

} // namespace quadphase
