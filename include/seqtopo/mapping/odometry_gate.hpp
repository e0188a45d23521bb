#pragma once
// Loop closures checked against odometry before they shape the map.
//
// Why: images alone cannot tell two identical corridors apart, nor a long featureless corridor from
// itself a few metres further on; a sequence alignment that matches them is confident and wrong, and one
// wrong merge joins two parts of the map. Odometry drifts, but slowly: two images taken d metres of travel
// apart cannot be at the same place if odometry puts them much farther apart than its drift over d allows.
// An aligned pair (i, j) is consistent when
//     |p_i - p_j| <= base + drift * (distance travelled between j and i)   (odometry positions p)
// and an alignment is kept when at least `min_consistent` of its pairs are.
//
// Distance alone misses look-alikes that the robot passes close by: two identical corridors side by side, or
// a corridor walked out and back whose far end looks like its near end. Such an alignment pairs two
// traversals that move *against* the alignment's direction (a forward alignment of two passes going opposite
// ways, a reverse one of two passes going the same way), and at mid-corridor its images are close. The rigid
// motion superposing the alignment's two traversals (below) tells: for a revisit it turns by the heading
// odometry drifted between them, for such a look-alike by about half a turn. An alignment is also
// inconsistent when that rotation exceeds a right angle (a revisit may cross its first pass at any angle)
// plus `turn` x (the median metres travelled between its pairs). The rotation is only read when the paired
// stretch spans at least 1 m (rms about its centre); a shorter one's direction is a few frames' jitter.
//
// Where two paths share a stretch and then part at a junction, the images just past the junction still
// look alike from both arms (they see the junction), so a local alignment runs on a few metres past it and
// merges places of different arms. Odometry's shape over a few metres is nearly exact, so the kept
// alignments are trimmed: the two traversals of an alignment's middle are superposed by a rigid motion
// (2-D Procrustes: rotation and translation, so a parallel lane or a reverse pass fits as well), and the
// alignment is extended outwards pair by pair while each new pair still lies within a tolerance of that
// superposition, refitted on the last `trim_window` metres of accepted pairs (odometry drifts over long
// distances, not short ones). The tolerance is three times the middle's own scatter about its superposition
// (a zig-zagging pass or noisy odometry scatters more), within [trim_floor, base]. A lateral offset between
// the traversals costs nothing; two paths that bend apart do.
#include <cstddef>
#include <span>
#include <string_view>
#include <vector>

#include "seqtopo/align/local_alignment.hpp"
#include "seqtopo/core/pose2.hpp"

namespace seqtopo::mapping {

struct OdometryGate {
  double base = 2.0;            // [m] allowed distance between the two images at zero travel
  double drift = 0.1;           // [m per m travelled] growth of the allowance
  double min_consistent = 0.5;  // fraction of an alignment's pairs that must be consistent
  double trim_window = 10.0;    // [m] travel over which the two traversals' shapes are compared (0: no trimming)
  double trim_floor = 1.0;      // [m] the least tolerance of the trimming (at most base)
  double turn = 0.005;          // [rad per m travelled] heading drift allowed beyond a right angle (see above)
};

// What the gate says of an alignment: consistent, its images too far apart, or its traversals turned against
// each other (the distance test is read first).
enum class OdometryVerdict { consistent, apart, turned };
std::string_view verdict_name(OdometryVerdict verdict);  // "consistent", "apart", "turned"

// One verdict per alignment. Throws std::invalid_argument when a pair indexes past the odometry or a setting is
// negative / NaN (min_consistent must be in [0, 1]).
std::vector<OdometryVerdict> odometry_verdicts(const std::vector<align::LocalAlignment>& alignments,
                                               std::span<const Pose2> odometry, const OdometryGate& gate = {});

// One flag per alignment: true = consistent with the odometry (distance and rotation, above). Throws like
// odometry_verdicts().
std::vector<bool> consistent_with_odometry(const std::vector<align::LocalAlignment>& alignments,
                                           std::span<const Pose2> odometry, const OdometryGate& gate = {});

// Per alignment, how well it agrees: the median over its pairs of their odometry distance over the gate's
// allowance (base + drift x travelled between them); 0 is perfect, the gate passes about those at or below 1
// (exactly so with min_consistent 0.5), an alignment without pairs is infinite. Throws like
// consistent_with_odometry().
std::vector<double> odometry_agreement(const std::vector<align::LocalAlignment>& alignments,
                                       std::span<const Pose2> odometry, const OdometryGate& gate = {});

// Each alignment cut to the pairs that stay within the tolerance of the rigid superposition of its two
// traversals (see above): a contiguous run of its pairs around the middle; a_begin..b_end span them again. An
// alignment stays as it is when the middle's traversals cannot be superposed within gate.base (the gate judges
// those), when the robot did not move over the middle (nothing to compare), or when gate.trim_window is 0.
// Throws like consistent_with_odometry().
std::vector<align::LocalAlignment> trim_to_odometry(const std::vector<align::LocalAlignment>& alignments,
                                                    std::span<const Pose2> odometry, const OdometryGate& gate = {});

}  // namespace seqtopo::mapping
