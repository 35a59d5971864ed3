// HEDRA_ASSERT: checks for programming errors (broken invariants inside the
// library), never for bad input: bad input travels as a status or an error
// value. On when NDEBUG is unset (CMake's Debug; its Release, RelWithDebInfo
// and MinSizeRel define NDEBUG, so off there) or when HEDRA_ENABLE_ASSERTS is
// defined (the CMake option -DHEDRA_ENABLE_ASSERTS=ON defines it for the
// libraries and everything linking them; the fuzz preset sets it). An
// embedder can route failures to its own handler by defining
// HEDRA_ASSERT_HANDLER(expr, file, line) before including any hedra header.
#pragma once

#include <cstdio>
#include <cstdlib>

#if !defined(NDEBUG) || defined(HEDRA_ENABLE_ASSERTS)
#  define HEDRA_ASSERTS_ENABLED 1
#else
#  define HEDRA_ASSERTS_ENABLED 0
#endif

#ifndef HEDRA_ASSERT_HANDLER
#  define HEDRA_ASSERT_HANDLER(expr, file, line) \
    (std::fprintf(stderr, "%s:%d: hedra assertion failed: %s\n", file, line, expr), std::abort())
#endif

#if HEDRA_ASSERTS_ENABLED
#  define HEDRA_ASSERT(expr) \
    ((expr) ? static_cast<void>(0) : static_cast<void>(HEDRA_ASSERT_HANDLER(#expr, __FILE__, __LINE__)))
#else
#  define HEDRA_ASSERT(expr) static_cast<void>(0)
#endif
