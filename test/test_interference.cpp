/*
 * The interference study on simulated data (the paper's Sect. 4): three sensors in a triangle
 * around the paper's box on a plate, 1, 2 or 3 projectors active.
 *  - The relation histogram's peaks sit at Table 2's angles and distances.
 *  - The inlier percentage rises with the neighbourhood radius and falls as projectors are
 *    added (Fig. 13).
 *  - The top face, lit by all three projectors, degrades most; the sides, lit by one or two,
 *    much less (the discussion of Fig. 11i).
 * Full VGA images as in the paper, one frame per sensor, spacing 4 px, fixed seeds.
 */
#include "interference_study.h"

#include <pcl/exceptions.h>

#include <gtest/gtest.h>

#include <cmath>
#include <map>

using namespace pcl::texlet;

namespace
{

/** Cells of the simulated study for the given projector counts and radii. */
std::map<std::pair<int, int>, InterferenceCell>
runStudy (const std::vector<int> &projectors, const std::vector<int> &radii)
{
  SimulatedSetup setup;
  const KnownObject object = simulatedObject (setup);
  std::map<std::pair<int, int>, InterferenceCell> cells;
  for (int p : projectors)
  {
    const auto recordings = simulateInterferenceRecordings (setup, p);
    for (int r : radii)
      cells[{p, r}] = runInterferenceCell (recordings, p, studyTexletParameters (r), object);
  }
  return cells;
}

} // namespace

TEST (InterferenceStudy, SimulatedSetupIsThePapersTriangle)
{
  SimulatedSetup setup;
  setup.width = 160;
  setup.height = 120;
  const auto recordings = simulateInterferenceRecordings (setup, 2);
  ASSERT_EQ (recordings.size (), 3u);
  const Eigen::Vector3d centre (0, 0, 0.12);
  for (std::size_t s = 0; s < 3; ++s)
  {
    const auto &r = recordings[s];
    EXPECT_EQ (r.name, "sensor_" + std::to_string (s));
    ASSERT_EQ (r.frames.size (), 1u);
    EXPECT_EQ (r.frames[0].width, 160);
    // 1 m from the box centre, looking at it, 45 degrees above the plate, 120 degrees apart.
    const Eigen::Vector3d eye = r.pose.translation ();
    EXPECT_NEAR ((eye - centre).norm (), 1.0, 1e-9);
    EXPECT_NEAR (r.pose.linear ().col (2).dot ((centre - eye).normalized ()), 1.0, 1e-9);
    EXPECT_NEAR (std::asin ((eye - centre).z ()) * 180 / M_PI, 45.0, 1e-9);
    const double az = std::atan2 (eye.y (), eye.x ()) * 180 / M_PI;
    EXPECT_NEAR (std::remainder (az - (-90.0 + 120.0 * s), 360.0), 0.0, 1e-9);
  }
  EXPECT_THROW (simulateInterferenceRecordings (setup, 0), pcl::BadArgumentException);
  EXPECT_THROW (simulateInterferenceRecordings (setup, 4), pcl::BadArgumentException);
}

TEST (InterferenceStudy, RelationPeaksSitAtTable2)
{
  const auto cells = runStudy ({1}, {6});
  const RelationStatistics &s = cells.at ({1, 6}).statistics;
  ASSERT_GT (s.texlets, 3000u);
  // Point relations of Table 2: the fullest bin within 7 mm / 20 degrees is the expected one's
  // (2 mm x 1 degree bins: within one bin of it) and stands far above the window's typical bin.
  struct Expect
  {
    const char *name;
    double mm, deg;
  };
  for (const Expect e : {Expect{"top vs ground", 240, 0}, Expect{"opposite sides (x)", 128, 180},
                         Expect{"opposite sides (y)", 112, 180}, Expect{"same plane", 0, 0}})
  {
    const RelationPeak p = s.peakNear (e.mm / 1000.0, e.deg, 0.007, 20.0);
    EXPECT_NEAR (p.distance_m * 1000.0, e.mm, 2.0 + 1e-9) << e.name;
    EXPECT_NEAR (p.angle_deg, e.deg, 1.0 + 1e-9) << e.name;
    // Against the same window shifted 30 degrees away from the relation.
    const RelationPeak off = s.peakNear (e.mm / 1000.0, e.deg > 90 ? e.deg - 30 : e.deg + 30, 0.007, 5.0);
    EXPECT_GT (p.count, 20 * std::max<std::uint64_t> (off.count, 1)) << e.name;
  }
  // Orthogonal planes: along the 90 degree line the angle peaks at 90 at every distance up to
  // the box's height, and the line ends there.
  for (double mm : {20.0, 100.0, 200.0})
  {
    const RelationPeak p = s.peakNear (mm / 1000.0, 90.0, 0.001, 30.0);
    EXPECT_NEAR (p.angle_deg, 90.0, 1.0 + 1e-9) << mm << " mm";
  }
  const RelationPeak inside = s.peakNear (0.2, 90.0, 0.001, 0.5), beyond = s.peakNear (0.27, 90.0, 0.001, 0.5);
  EXPECT_GT (inside.count, 30 * std::max<std::uint64_t> (beyond.count, 1));
  // Every relation of Table 2 is found, and with one projector most relations are inliers.
  for (std::size_t r = 0; r < s.relations.size (); ++r)
    EXPECT_GT (s.relation_hits[r], 1000u) << s.relations[r].name;
  EXPECT_GT (s.inlierPercent (), 85.0);
}

TEST (InterferenceStudy, InliersRiseWithRadiusAndFallWithProjectors)
{
  const std::vector<int> projectors{1, 2, 3}, radii{2, 6, 10};
  const auto cells = runStudy (projectors, radii);
  for (int p : projectors)
    for (int r : radii)
      std::cout << "projectors " << p << ", radius " << r << ": " << cells.at ({p, r}).statistics.texlets
                << " texlets, " << cells.at ({p, r}).statistics.inlierPercent () << " % inliers\n";
  for (int p : projectors)
    for (std::size_t k = 1; k < radii.size (); ++k)
      EXPECT_GT (cells.at ({p, radii[k]}).statistics.inlierPercent (),
                 cells.at ({p, radii[k - 1]}).statistics.inlierPercent ())
          << p << " projectors, radius " << radii[k - 1] << " -> " << radii[k];
  for (int r : radii)
    for (std::size_t k = 1; k < projectors.size (); ++k)
      EXPECT_LT (cells.at ({projectors[k], r}).statistics.inlierPercent (),
                 cells.at ({projectors[k - 1], r}).statistics.inlierPercent ())
          << "radius " << r << ", projectors " << projectors[k - 1] << " -> " << projectors[k];
  // Interference also punches holes: fewer texlets at the smallest radius as projectors are added.
  EXPECT_LT (cells.at ({3, 2}).statistics.texlets, cells.at ({1, 2}).statistics.texlets);
}

TEST (InterferenceStudy, TopFaceSeenByAllProjectorsDegradesMost)
{
  const auto cells = runStudy ({1, 3}, {6});
  const InterferenceCell &one = cells.at ({1, 6}), &three = cells.at ({3, 6});
  const KnownObject object = simulatedObject (SimulatedSetup ());
  ASSERT_EQ (one.faces.size (), object.faces.size ());
  const int top = object.faceIndex ("top"), ground = object.faceIndex ("ground");
  // Texlet level: the median normal error grows most on the top face.
  const double top_growth = three.faces[top].median_angle_deg / one.faces[top].median_angle_deg;
  std::cout << "median normal error growth 1 -> 3 projectors: top " << top_growth;
  for (const char *side : {"side +x", "side -x", "side +y", "side -y"})
  {
    const int f = object.faceIndex (side);
    ASSERT_GT (one.faces[f].texlets, 100u) << side;
    const double growth = three.faces[f].median_angle_deg / one.faces[f].median_angle_deg;
    std::cout << ", " << side << " " << growth;
    EXPECT_GT (top_growth, growth + 0.3) << side;
  }
  std::cout << "\n";
  EXPECT_GT (top_growth, 1.5);
  // Relation level (Fig. 11i): the top-vs-ground peak loses far more inliers than the
  // opposite-sides peaks.
  const auto drop = [&] (const char *a, const char *b) {
    const int fa = object.faceIndex (a), fb = object.faceIndex (b);
    return one.statistics.labelPairInlierPercent (fa, fb) - three.statistics.labelPairInlierPercent (fa, fb);
  };
  const double top_ground = drop ("top", "ground");
  std::cout << "inlier drop (points): top-ground " << top_ground << ", sides x " << drop ("side +x", "side -x")
            << ", sides y " << drop ("side +y", "side -y") << "\n";
  EXPECT_GT (top_ground, 5.0);
  EXPECT_GT (top_ground, 3.0 * drop ("side +x", "side -x"));
  EXPECT_GT (top_ground, 3.0 * drop ("side +y", "side -y"));
  (void) ground;
}

TEST (InterferenceStudy, MergedTexletsKeepTheirSensorAndLieOnTheObject)
{
  SimulatedSetup setup;
  setup.width = 320;
  setup.height = 240;
  const auto recordings = simulateInterferenceRecordings (setup, 1);
  const MergedTexlets m = extractMergedTexlets (recordings, studyTexletParameters (4, 4));
  const KnownObject object = simulatedObject (setup);
  const auto labels = labelTexlets (m.texlets, object);
  std::size_t on_object = 0;
  for (std::size_t s = 0; s < 3; ++s)
    EXPECT_GT (m.countFrom (static_cast<std::uint16_t> (s)), 200u) << s;
  for (std::size_t i = 0; i < m.texlets.size (); ++i)
    on_object += labels[i] >= 0 ? 1 : 0;
  // In the box's frame nearly every texlet lies on a face of the box or the plate.
  EXPECT_GT (static_cast<double> (on_object) / m.texlets.size (), 0.97);
  // Each sensor sees the side facing it: sensor 0 (on the -y side) sees side -y, never side +y.
  std::map<std::pair<int, int>, int> seen;
  for (std::size_t i = 0; i < m.texlets.size (); ++i)
    ++seen[{m.sensor[i], labels[i]}];
  EXPECT_GT ((seen[{0, object.faceIndex ("side -y")}]), 50);
  EXPECT_EQ ((seen[{0, object.faceIndex ("side +y")}]), 0);
  EXPECT_GT ((seen[{1, object.faceIndex ("side +x")}]), 50);
  EXPECT_GT ((seen[{2, object.faceIndex ("side -x")}]), 50);
}
