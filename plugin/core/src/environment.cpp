// SPDX-License-Identifier: MIT
// The QUADPHASE_* variables, ignored in secure-execution mode: see environment.h.
#ifndef _GNU_SOURCE
#define _GNU_SOURCE 1 // glibc declares secure_getenv only with it (g++ defines it already on Linux)
#endif
#include "environment.h"

#include <cstdlib>
#include <cstring>

// Which test of secure-execution mode the C library offers. glibc has had secure_getenv since 2.17.
#if defined(__GLIBC__) && (__GLIBC__ > 2 || (__GLIBC__ == 2 && __GLIBC_MINOR__ >= 17))
#define QUADPHASE_ENV_SECURE_GETENV 1
#elif defined(__linux__) && __has_include(<sys/auxv.h>)
#include <sys/auxv.h>
#define QUADPHASE_ENV_AUXV 1
#elif defined(__APPLE__) || defined(__FreeBSD__) || defined(__NetBSD__) || defined(__OpenBSD__) ||           \
    defined(__DragonFly__)
#include <unistd.h>
#define QUADPHASE_ENV_ISSETUGID 1
#endif

namespace quadphase
{
namespace detail
{

const char* EnvironmentValue(const char* name)
{
#if defined(QUADPHASE_ENV_SECURE_GETENV)
    return secure_getenv(name);
#elif defined(QUADPHASE_ENV_AUXV)
    return getauxval(AT_SECURE) != 0 ? nullptr : std::getenv(name);
#elif defined(QUADPHASE_ENV_ISSETUGID)
    return issetugid() != 0 ? nullptr : std::getenv(name);
#else
    return std::getenv(name);
#endif
}

bool EnvironmentFlag(const char* name)
{
    const char* value = EnvironmentValue(name);
    return value != nullptr && value[0] != '\0' && std::strcmp(value, "0") != 0;
}

} // namespace detail
} // namespace quadphase
