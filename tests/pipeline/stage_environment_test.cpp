// The environment the driver starts the stages with (pipeline::stage_environment): the caller's,
// with transparent huge pages asked of glibc's malloc unless the caller decided otherwise.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "stage_main.h"

namespace volts {
namespace {

std::vector<std::string> environment_of(std::vector<std::string> vars) {
  std::vector<char*> env;
  for (auto& v : vars) env.push_back(v.data());
  env.push_back(nullptr);
  return pipeline::stage_environment(env.data());
}

TEST(StageEnvironment, AddsHugePagesToTheCallersEnvironmentUnlessItSetsThem) {
  // No tunables: one is added, everything else is passed on in order.
  EXPECT_EQ(environment_of({"PATH=/usr/bin", "HOME=/root"}),
            (std::vector<std::string>{"PATH=/usr/bin", "HOME=/root", "GLIBC_TUNABLES=glibc.malloc.hugetlb=1"}));
  EXPECT_EQ(environment_of({}), (std::vector<std::string>{"GLIBC_TUNABLES=glibc.malloc.hugetlb=1"}));
  // Other tunables: appended to them.
  EXPECT_EQ(environment_of({"GLIBC_TUNABLES=glibc.malloc.arena_max=2", "X=1"}),
            (std::vector<std::string>{"GLIBC_TUNABLES=glibc.malloc.arena_max=2:glibc.malloc.hugetlb=1", "X=1"}));
  EXPECT_EQ(environment_of({"GLIBC_TUNABLES="}), (std::vector<std::string>{"GLIBC_TUNABLES=glibc.malloc.hugetlb=1"}));
  // The caller's own choice stands, off included.
  EXPECT_EQ(environment_of({"GLIBC_TUNABLES=glibc.malloc.hugetlb=0"}), (std::vector<std::string>{"GLIBC_TUNABLES=glibc.malloc.hugetlb=0"}));
  EXPECT_EQ(environment_of({"GLIBC_TUNABLES=glibc.malloc.hugetlb=2:glibc.malloc.arena_max=1"}),
            (std::vector<std::string>{"GLIBC_TUNABLES=glibc.malloc.hugetlb=2:glibc.malloc.arena_max=1"}));
  // A variable that only ends in the name is not it.
  EXPECT_EQ(environment_of({"MY_GLIBC_TUNABLES=a"}), (std::vector<std::string>{"MY_GLIBC_TUNABLES=a", "GLIBC_TUNABLES=glibc.malloc.hugetlb=1"}));
}

}  // namespace
}  // namespace volts
