// The processor named in rows that quote speed (core/cpu_model.h).
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "core/cpu_model.h"

TEST(CpuModel, IsTheFirstModelNameOfProcCpuinfo) {
  std::ifstream in("/proc/cpuinfo");
  std::string line, expected;
  while (expected.empty() && std::getline(in, line))
    if (line.rfind("model name", 0) == 0) expected = line.substr(line.find(": ") + 2);
  if (expected.empty()) GTEST_SKIP() << "no 'model name' in /proc/cpuinfo on this machine";
  EXPECT_EQ(nsf::cpu_model(), expected);
  EXPECT_EQ(nsf::cpu_model().find('\n'), std::string::npos);
}
