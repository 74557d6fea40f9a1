/*
 * pcl_texlet GPU tests: noisy texlets on the faces of the paper's Table 2 box, with their face labels
 * and the box's expected relations, for the relation tests and the benchmark on machines
 * without PCL (the simulator needs PCL).
 */
#pragma once

#include <pcl_texlet/kernels/relation_histogram.h>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace pcl_texlet_test
{

/** \brief Texlets as the relation kernels take them (unit normals), labelled by face. */
struct BoxTexlets
{
  std::vector<pcl::texlet::kernels::Vec3<float>> centre, normal;
  std::vector<int> label; ///< face 0-4: -x, +x, -y, +y, top

  /** \brief The kernels' view of these texlets, with or without the labels. */
  pcl::texlet::kernels::RelationInput<float>
  input (bool labelled) const
  {
    pcl::texlet::kernels::RelationInput<float> in;
    in.centre = centre.data ();
    in.normal = normal.data ();
    in.label = labelled ? label.data () : nullptr;
    in.count = static_cast<int> (centre.size ());
    return in;
  }
};

/** \brief \a per_face texlets on each of the five visible faces (not the bottom) of the box of
  * 128 x 112 x 240 mm centred 1 m away along z: centres 1 mm off the face, normals 0.03 rad off
  * (Gaussian, std::mt19937 seeded with \a seed).
  */
inline BoxTexlets
syntheticBoxTexlets (int per_face, std::uint32_t seed)
{
  const double size[3] = {0.128, 0.112, 0.240};
  std::mt19937 rng (seed);
  std::uniform_real_distribution<double> u (-0.5, 0.5);
  std::normal_distribution<double> position_noise (0.0, 0.001), normal_noise (0.0, 0.03);
  BoxTexlets t;
  int face = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = -1; side <= 1; side += 2)
    {
      if (axis == 2 && side < 0)
        continue; // the bottom stands on the plate
      for (int k = 0; k < per_face; ++k)
      {
        double p[3], n[3] = {0, 0, 0};
        for (int a = 0; a < 3; ++a)
          p[a] = u (rng) * size[a];
        p[axis] = 0.5 * side * size[axis] + position_noise (rng);
        n[axis] = side;
        for (double &c : n)
          c += normal_noise (rng);
        const double len = std::sqrt (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        t.centre.push_back ({float (p[0]), float (p[1]), float (p[2] + 1.0)});
        t.normal.push_back ({float (n[0] / len), float (n[1] / len), float (n[2] / len)});
        t.label.push_back (face);
      }
      ++face;
    }
  return t;
}

/** \brief The box's expected relations (10 degrees, 5 mm boxes): a face with itself (0 deg,
  * 0 mm), opposite faces (180 deg at 128, 112 and 240 mm), orthogonal faces (90 deg, 0-240 mm).
  */
inline std::vector<pcl::texlet::kernels::RelationBox>
syntheticBoxRelations ()
{
  std::vector<pcl::texlet::kernels::RelationBox> boxes (5);
  boxes[0].angle_deg = 0.0f;
  boxes[1].angle_deg = 180.0f;
  boxes[1].distance_min = boxes[1].distance_max = 0.128f;
  boxes[2].angle_deg = 180.0f;
  boxes[2].distance_min = boxes[2].distance_max = 0.112f;
  boxes[3].angle_deg = 90.0f;
  boxes[3].distance_max = 0.240f;
  boxes[4].angle_deg = 180.0f;
  boxes[4].distance_min = boxes[4].distance_max = 0.240f;
  return boxes;
}

} // namespace pcl_texlet_test
