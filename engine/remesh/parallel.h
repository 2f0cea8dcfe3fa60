// Section 6's remeshing loop on several threads, by regions (the partition +
// frozen interface scheme of ParMmg, in one process; remesh/partition.h):
//  1. T_1 is split into regions_per_thread x threads regions of about
//     equal predicted work;
//  2. each region is cut out with its border frozen (required) and runs the
//     whole schedule (Remesher::run) on one of the threads, which take the
//     regions in turn, with its own copies of the search structures of T_G
//     and T_0 (copy_for_thread);
//  3. the regions are pasted back in order, and the band of `band_rings`
//     rings around their borders, left as it was by step 2, runs the
//     schedule again (its own border, inside the remeshed regions, frozen):
//     for a coarsening in pieces on the threads as in step 2 (band_pieces),
//     then the band around the seams between the pieces, on one.
// The output depends on the mesh, the options and the region count only
// (a function of the thread count; not on the threads' timing). The regions
// and the band run the serial loop's passes, so the mean figures (band,
// mean quality) match the serial loop's; the least quality is that of one
// triangle, a local optimum the order of the operations decides, and moves
// either way with the region count. The serial loop runs when threads is 1
// or the mesh is too small to share.
#pragma once
#include <functional>
#include <vector>

#include "remesh/remesher.h"

namespace anisurf::remesh {

struct ParallelOptions {
  int threads = 1;  // regions remeshed at once (1: the serial Remesher::run)
  // Regions per thread, taken in turn by the threads as they finish: the
  // predicted work of a region (its output) is not its time, which depends
  // on how far the metric is from the mesh.
  int regions_per_thread = 3;
  // A coarsening (the predicted output under half the input's triangles)
  // takes this many regions per thread instead: its work is the collapses,
  // whose cost in a region depends on how many rounds the region takes to
  // settle (a strongly anisotropic part of the metric takes more), which no
  // estimate from the input sees; smaller regions let the threads even it
  // out. A refinement keeps the fewer, larger regions (fewer borders).
  int coarsening_regions_per_thread = 4;
  // Each region needs at least this much predicted work (triangle_work:
  // about the triangles it holds and will hold): a smaller mesh is remeshed
  // by fewer regions. One round (a region per thread) asks min_region_work
  // of each; more regions than threads, min_round_work of each (every region
  // adds a border to remesh again in the band, serially). A few thousand
  // triangles already pay for a region: where a metric from curvature meets
  // a CAD part's creases every operation checks the input around it, and
  // the rounds, not the triangles, make the time.
  double min_region_work = 3000;
  // In a refinement with several rounds, each round's regions get this
  // share of the previous round's predicted work (every thread's sum stays
  // the same: the threads take the regions in turn). A finished region
  // waits for the paste holding about half the bytes a running one holds at
  // its top: larger regions first, smaller ones running beside those that
  // wait, even out the memory of the rounds (sphere20k_bandfine, 2 rounds
  // of 2: peak 71.8-72.5k KiB at 0.5, 70.6-71.0k at 0.6, 71.5k at 0.7,
  // 74.4-75.2k with equal regions). 1: equal regions. A coarsening keeps
  // equal regions (its regions shrink as they run).
  double later_round_share = 0.6;
  double min_round_work = 20000;
  int band_rings = 4;  // step 3: rings around the borders remeshed again
  // ... in a coarsening: its regions' borders keep the input's fine vertices
  // while the regions beside them coarsen, so each ring out of a border
  // reaches about one output size further. The band's outer ring is frozen:
  // three rings leave the strip of fine vertices and two rings of coarse
  // ones free to rearrange once the strip is collapsed (two: sphere500k_band
  // ungraded ends with 94.7% of its edges in band instead of 99.5%).
  int coarsening_band_rings = 3;
  // Step 3 of a coarsening in pieces: the band is split as the mesh was (one
  // piece per thread, each of min_piece_work at least), the pieces remeshed
  // at once with their seams frozen, then the band of band_rings rings
  // around the seams alone (false: the whole band on one thread). A
  // coarsening's band is the rounds of a CAD part's creases and curvature
  // (falcon.mesh at hausd 3e-4 ungraded: a quarter of the remeshing time, on
  // one thread); a refinement's is a small share of its time, and its pieces
  // at once hold more memory than the whole band (sphere20k_bandfine: peak
  // 74.4 -> 78.6 MB): it stays whole.
  bool band_pieces = true;
  double min_piece_work = 1500;
};

// The number of regions run_in_regions() uses for `m` (1: serial; above the
// thread count, a multiple of it).
int region_count(const AdaptedMesh& m, const ParallelOptions& p);
// The predicted work of each of the n regions as a share (summing to 1):
// round r = k / threads of a refinement gets later_round_share^r of the
// first's per region; equal shares for one round or a coarsening.
std::vector<double> region_shares(const AdaptedMesh& m, const ParallelOptions& p, int n);

// Remesher::run() over the regions (see the top of this file); returns the
// passes of every region, in region order, then those of the band (each
// with PassReport::region set; `touched` left empty: the slots are the
// regions'). `progress` is called after each pass, from the region's
// thread, one call at a time. A region that goes over its share of the
// growth limits (RemeshOptions::max_vertices, max_round_vertices) stops
// everything: its passes come last, the last one over_limit (the mesh is
// valid, not adapted).
std::vector<PassReport> run_in_regions(AdaptedMesh& m, const RemeshOptions& options, const ParallelOptions& p,
                                       const std::function<void(const PassReport&)>& progress = {});

}  // namespace anisurf::remesh
