// ReserveDomain: test processes running at once never get the same DDS domain. Domains are
// only lock-file names here (9000..9002, which no test uses for DDS), so nothing is opened.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <set>
#include <stdexcept>
#include <vector>

#include "tests/common/transport/test_samples.h"

namespace srics::transport::testing {
namespace {

constexpr int kFirst = 9000, kCount = 3;

// A child process that reserves a domain of the range, writes it (or -1 when every domain is
// held) to `report`, then holds it until the parent closes `release`'s write end.
pid_t ReservingChild(int report, const int release[2]) {
  const pid_t pid = fork();
  if (pid != 0) return pid;
  close(release[1]);
  int domain = -1;
  try {
    domain = ReserveDomain(kFirst, kCount);
  } catch (const std::runtime_error&) {
  }
  if (write(report, &domain, sizeof domain) != sizeof domain) _exit(3);
  char byte;
  while (read(release[0], &byte, 1) > 0) {
  }
  _exit(0);
}

TEST(ReserveDomainTest, ProcessesHoldingDomainsAtOnceGetDifferentOnesAndTheFullRangeIsAnError) {
  const int mine = ReserveDomain(kFirst, kCount);
  EXPECT_EQ(ReserveDomain(kFirst, kCount), mine) << "the same range twice in one process";
  int report[2], release[2];
  ASSERT_EQ(pipe(report), 0);
  ASSERT_EQ(pipe(release), 0);
  std::vector<pid_t> children;
  std::set<int> held = {mine};
  for (int k = 0; k < kCount; ++k) {  // the last one finds every domain held
    children.push_back(ReservingChild(report[1], release));
    int domain = 0;
    ASSERT_EQ(read(report[0], &domain, sizeof domain), static_cast<ssize_t>(sizeof domain));
    if (k < kCount - 1) {
      EXPECT_GE(domain, kFirst);
      EXPECT_LT(domain, kFirst + kCount);
      EXPECT_TRUE(held.insert(domain).second) << "domain " << domain << " given twice";
    } else {
      EXPECT_EQ(domain, -1) << "every domain was held, yet " << domain << " was given";
    }
  }
  close(release[1]);
  for (const pid_t child : children) {
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  }
  // the children's domains were released when they exited: a new process gets one again
  ASSERT_EQ(pipe(release), 0);
  const pid_t again = ReservingChild(report[1], release);
  int domain = -1;
  ASSERT_EQ(read(report[0], &domain, sizeof domain), static_cast<ssize_t>(sizeof domain));
  EXPECT_NE(domain, -1);
  EXPECT_NE(domain, mine);
  close(release[1]);
  waitpid(again, nullptr, 0);
}

}  // namespace
}  // namespace srics::transport::testing
