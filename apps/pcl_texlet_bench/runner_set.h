/*
 * pcl_texlet_bench: the methods of one study bound to one frame, ready for timeInterleaved.
 */
#pragma once

#include "methods.h"

#include <memory>
#include <vector>

namespace pcl_texlet_bench
{

/** \brief One runner per method spec, owned, and the same as the plain pointers the harness takes. */
struct RunnerSet
{
  std::vector<std::unique_ptr<MethodRunner>> owned;
  std::vector<MethodRunner *> runners;
};

/** \brief makeRunner for each of \a specs, in their order, on the same cloud, centres and camera. */
inline RunnerSet
makeRunners (const std::vector<MethodSpec> &specs, const Setup &setup, const Cloud::ConstPtr &cloud,
             const pcl::IndicesConstPtr &centres, const std::vector<int> &valid_disc,
             const pcl::texlet::CameraModel::ConstPtr &camera)
{
  RunnerSet set;
  for (const MethodSpec &spec : specs)
  {
    set.owned.push_back (makeRunner (spec, setup, cloud, centres, valid_disc, camera));
    set.runners.push_back (set.owned.back ().get ());
  }
  return set;
}

} // namespace pcl_texlet_bench
