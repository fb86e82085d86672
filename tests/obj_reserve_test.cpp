// The OBJ reader reserves its arrays either for the most lines the text could hold (where
// unused reservations are free) or for the lines it counts (under an address-space or data
// limit, or strict commit): the same soup either way.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <string>

#include "common/zeroed_array.h"
#include "mesh/obj_io.h"
#include "test_meshes.h"

namespace ffd {
namespace {

bool same_soup(const PolygonSoup& a, const PolygonSoup& b) {
  return a.positions == b.positions && a.elements.corners == b.elements.corners &&
         a.elements.kinds == b.elements.kinds && a.elements.offsets == b.elements.offsets &&
         a.elements.lines == b.elements.lines;
}

// bunny.obj, and text with quads, a polygon, points and lines past the counted triangles.
std::vector<std::string> texts() {
  return {test::read_file(std::string(FFD_TEST_DATA) + "/bunny.obj"),
          "# comment\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nf 1 2 3 4\nf 1 2 5\np 3\nl 1 5\nf 2 3 4 5 1\n"};
}

TEST(ObjReserve, ReadsTheSameSoupWhetherItReservesTheBoundOrCountsLines) {
  const std::vector<std::string> inputs = texts();
  std::vector<PolygonSoup> here;
  for (const std::string& text : inputs) here.push_back(read_obj(text, "in.obj"));
  // Here the arrays hold the bound when reservations are free (the usual machine), else
  // exactly what was counted.
  const std::size_t bunny_bound = (inputs[0].size() + 1) / 8;
  EXPECT_EQ(here[0].positions.capacity(), reserving_is_free(1) ? bunny_bound : here[0].positions.size());
  // A child under a (huge) data limit must count, and read the same soups.
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    rlimit limit{};
    getrlimit(RLIMIT_DATA, &limit);
    limit.rlim_cur = limit.rlim_max == RLIM_INFINITY ? RLIM_INFINITY - 1 : limit.rlim_max;
    if (setrlimit(RLIMIT_DATA, &limit) != 0 || reserving_is_free(1)) _exit(3);
    try {
      for (std::size_t i = 0; i < inputs.size(); ++i) {
        const PolygonSoup counted = read_obj(inputs[i], "in.obj");
        if (!same_soup(counted, here[i])) _exit(4);
        if (counted.positions.capacity() != counted.positions.size()) _exit(5);
      }
    } catch (...) {
      _exit(6);
    }
    _exit(0);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "3: the limit did not make reservations costly; 4: another soup; 5: not counted; 6: the read threw";
}

TEST(ObjReserve, ReservingIsNotFreeBeyondAQuarterOfTheMachinesMemory) {
  const double memory = static_cast<double>(sysconf(_SC_PHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGESIZE));
  EXPECT_FALSE(reserving_is_free(static_cast<std::size_t>(memory / 4) + 4096));
}

}  // namespace
}  // namespace ffd
