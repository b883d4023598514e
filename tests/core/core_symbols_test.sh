#!/usr/bin/env bash
# The core's promises, checked on the built library: it may call nothing but a few C library
# functions. Any allocation (malloc, operator new), exception (__cxa_throw, personality
# routines), RTTI (typeinfo) or I/O symbol among its undefined references fails this test.
#   tests/core_symbols_test.sh path/to/libmvox_core.a
set -euo pipefail
library=$1
# libm's maths (the renderer's camera and lighting table) is allowed: it neither allocates nor
# throws.
# Unoptimised builds (Debug, MVOX_SANITIZE) also keep two traps that only abort: assert() in
# GLM's headers (__assert_fail) and the pure-virtual-call handler that abstract interfaces'
# vtables point at (__cxa_pure_virtual).
# _GLOBAL_OFFSET_TABLE_ is the linker's, referenced by position-independent code.
allowed='^(_GLOBAL_OFFSET_TABLE_|abort|memset|memcpy|memmove|ceil|nextafterf|__popcountdi2|__stack_chk_fail|__assert_fail|__cxa_pure_virtual|(atan|llround|lround|pow|sincos|sin|cos|sqrt|tan|floor)f?)$'
# The core's own symbols and sanitizer hooks (MVOX_SANITIZE builds) are not outside calls.
undefined=$(nm -u --format=posix "$library" | awk 'NF >= 2 {print $1}' | sort -u |
  grep -vE '^_ZN4mvox|^_ZNK4mvox|^__(asan|ubsan|sanitizer|lsan)_' || true)
unexpected=$(echo "$undefined" | grep -vE "$allowed" | grep -v '^$' || true)
if [ -n "$unexpected" ]; then
  echo "libmvox_core.a references symbols outside the core's allowance:"
  echo "$unexpected"
  exit 1
fi
echo "libmvox_core.a references only: $(echo $undefined)"
