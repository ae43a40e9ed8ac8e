// SPDX-License-Identifier: GPL-3.0-or-later
// A file path in the system's temporary folder that belongs to the running test alone.
//
// ctest runs every test in its own process, two at a time or more, so two tests that both write "columns.txt" read
// each other's files now and then. The path holds the test's name and the process id: no other test, and no other run
// of the suite on the same machine, writes it.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#ifdef _WIN32
#include <process.h>
#else
#include <unistd.h>
#endif

namespace plantmorph::testing
{

/// `<temp>/<prefix>_<pid>_<suite>.<test>_<name>`; `name` may hold a folder that does not exist.
inline std::string TemporaryPath(const std::string& prefix, const std::string& name)
{
#ifdef _WIN32
  const int pid = _getpid();
#else
  const int pid = static_cast<int>(getpid());
#endif
  std::string tag = prefix + "_" + std::to_string(pid) + "_";
  if (const auto* test = ::testing::UnitTest::GetInstance()->current_test_info())
    tag += std::string(test->test_suite_name()) + "." + test->name() + "_";
  return (std::filesystem::temp_directory_path() / (tag + name)).string();
}

} // namespace plantmorph::testing
