#pragma once
// Test support: what a call refused with, for tests of mvox::Error messages.
#include <gtest/gtest.h>

#include <functional>
#include <string>

namespace mvox::test {

// Runs `action`, which must throw mvox::Error, and returns its what(); records a test failure and
// returns "" when it throws something else or nothing.
std::string error_of(const std::function<void()>& action);

}  // namespace mvox::test

// EXPECT that `text` contains `part`, showing `text` when it does not. Each argument is evaluated
// once, so a failure is reported once.
#define EXPECT_CONTAINS(text, part)                                                 \
  do {                                                                              \
    const std::string mvox_expect_text_ = (text);                                   \
    EXPECT_NE(mvox_expect_text_.find(part), std::string::npos)                      \
        << "\"" << mvox_expect_text_ << "\" does not contain \"" << (part) << "\""; \
  } while (0)
