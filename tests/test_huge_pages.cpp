// Build arrays advised onto transparent huge pages (core/huge_pages.h): the
// contents are what the containers would hold anyway, and on Linux with
// THP available the advised range is eligible for huge pages in the
// kernel's own account (/proc/self/smaps), and a mapping not advised is not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <tbb/concurrent_vector.h>
#include <tbb/parallel_for.h>

#include "core/huge_pages.h"

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace mbrt::detail {
namespace {

// The THPeligible flag of the mapping that holds `p`, when the kernel says.
std::optional<bool> thpEligible(const void* p) {
  std::ifstream smaps("/proc/self/smaps");
  if (!smaps) return std::nullopt;
  const uintptr_t a = reinterpret_cast<uintptr_t>(p);
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    uintptr_t lo = 0, hi = 0;
    char dash = 0;
    std::istringstream head(line);
    if (head >> std::hex >> lo >> dash >> hi && dash == '-') {  // a mapping's first line
      inside = lo <= a && a < hi;
      continue;
    }
    if (inside && line.rfind("THPeligible:", 0) == 0) return line.find('1') != std::string::npos;
  }
  return std::nullopt;
}

bool hugePagesOnRequest() {
  std::ifstream f("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string s;
  std::getline(f, s);
  return s.find("[madvise]") != std::string::npos || s.find("[always]") != std::string::npos;
}

TEST(HugePages, ReservedVectorKeepsItsContentsAndCapacity) {
  std::vector<uint32_t> v = {7, 8, 9};
  reserveOnHugePages(v, size_t(3) << 20);  // 12 MiB: reallocates, copies the three
  ASSERT_GE(v.capacity(), size_t(3) << 20);
  EXPECT_EQ(v, (std::vector<uint32_t>{7, 8, 9}));
  const uint32_t* data = v.data();
  v.resize(size_t(3) << 20);
  std::iota(v.begin(), v.end(), 0u);
  EXPECT_EQ(v.data(), data);  // no reallocation: the advised block is the one written
  EXPECT_EQ(v.back(), (3u << 20) - 1);
  reserveOnHugePages(v, 10);  // smaller than the capacity: nothing happens
  EXPECT_EQ(v.data(), data);
}

TEST(HugePages, AdviceIsHarmlessOnAnyRange) {
  adviseHugePages(nullptr, size_t(1) << 30);
  std::vector<char> small(100, 'x');
  adviseHugePages(small.data(), small.size());
  adviseHugePages(small.data() + 1, 0);
  EXPECT_EQ(std::string(small.begin(), small.end()), std::string(100, 'x'));
}

TEST(HugePages, ConcurrentVectorGrowsWithTheAllocator) {
  tbb::concurrent_vector<uint64_t, HugePageAllocator<uint64_t>> v;
  tbb::parallel_for(0, 1 << 20, [&](int i) { v.push_back(uint64_t(i)); });
  ASSERT_EQ(v.size(), size_t(1) << 20);
  std::vector<uint64_t> sorted(v.begin(), v.end());
  std::sort(sorted.begin(), sorted.end());
  for (size_t i = 0; i < sorted.size(); ++i) ASSERT_EQ(sorted[i], i);
}

TEST(HugePages, AdvisedArraysAreEligibleAndOthersAreNot) {
#if !defined(__linux__)
  GTEST_SKIP() << "transparent huge pages are Linux's";
#else
  if (!hugePagesOnRequest()) GTEST_SKIP() << "this kernel gives no transparent huge pages (THP 'never')";
  std::vector<uint8_t> big;
  reserveOnHugePages(big, size_t(16) << 20);
  const uint8_t* middle = big.data() + (size_t(8) << 20);  // inside the advised 2 MiB pages
  const std::optional<bool> advised = thpEligible(middle);
  if (!advised) GTEST_SKIP() << "/proc/self/smaps has no THPeligible line for the array";
  std::ifstream f("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string mode;
  std::getline(f, mode);
  EXPECT_TRUE(*advised) << "an advised 16 MiB array is not eligible for huge pages (THP: " << mode << ")";
  if (mode.find("[madvise]") != std::string::npos) {
    // Not advised: a fresh anonymous 16 MiB mapping is not eligible (the
    // check above is not the kernel's answer for every mapping).
    const size_t bytes = size_t(16) << 20;
    void* plain = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    ASSERT_NE(plain, MAP_FAILED);
    const std::optional<bool> left = thpEligible(static_cast<char*>(plain) + bytes / 2);
    ::munmap(plain, bytes);
    ASSERT_TRUE(left.has_value());
    EXPECT_FALSE(*left);
  }
#endif
}

}  // namespace
}  // namespace mbrt::detail
