/* -*- c++ -*- ----------------------------------------------------------
   USER-NCF tests: a pass-through checker for chain scenes (engine-free).

   For every pair of segments that share no node and come within `reach` of each other, the side
   of B on which A lies (sign of the offset of the closest points along A x B) is recorded while
   the closest points are interior to both segments and the segments cross at more than a small
   angle. That signed distance is continuous as long as the axes do not meet, so a sign flip
   between two checks close enough in time means one axis went through the other: a chain passed
   through another. Periodic in x and y (minimum image), open in z. Also records the closest
   approach of any two such axes.
------------------------------------------------------------------------- */

#ifndef NCF_PASSTHROUGH_H
#define NCF_PASSTHROUGH_H

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

namespace ncftest {

class PassThroughChecker {
 public:
  // segs: node indices (0-based, into the position array) of every segment; lx, ly: periodic
  // box lengths (0: not periodic in that direction); reach: pairs farther apart (midpoints) are
  // not followed
  PassThroughChecker(std::vector<std::pair<int, int>> segs, double lx, double ly, double reach);
  // x: 3 * nnodes positions (wrapped or not)
  void check(const std::vector<double> &x);

  int flips = 0;             // sign flips seen so far (pass-throughs)
  double closest = 1e300;    // closest approach of two axes that share no node [m]
  long pairs_seen = 0;       // crossing pairs whose side was compared at least once

 private:
  std::vector<std::pair<int, int>> segs_;
  double lx_, ly_, reach_;
  std::unordered_map<std::uint64_t, signed char> side_;
};

}    // namespace ncftest

#endif
