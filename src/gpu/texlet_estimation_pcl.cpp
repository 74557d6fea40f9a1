/*
 * pcl_texlet GPU: conversion of the library's camera and noise models to the device's PODs.
 * Compiled only where PCL is present (it links libpcl_texlet).
 */
#include <pcl_texlet/gpu/texlet_estimation_pcl.h>
#include <pcl_texlet/camera/openni_fov_model.h>
#include <pcl_texlet/camera/pinhole_model.h>

#include <pcl/exceptions.h>

#include <sstream>

namespace pcl
{
namespace texlet
{
namespace gpu
{

DeviceCamera
toDeviceCamera (const texlet::CameraModel &camera)
{
  if (const auto *p = dynamic_cast<const texlet::PinholeModel *> (&camera))
    return DeviceCamera::pinhole (p->fx (), p->fy (), p->cx (), p->cy (), p->distortion ());
  if (const auto *o = dynamic_cast<const texlet::OpenNIFovModel *> (&camera))
    return DeviceCamera::openniFov (o->width (), o->height (), o->hfov (), o->vfov ());
  throw pcl::BadArgumentException ("pcl::texlet::gpu::toDeviceCamera: camera model '" + camera.name () +
                                   "' has no device form (only 'pinhole' and 'openni_fov')");
}

DeviceNoise
toDeviceNoise (const texlet::NoiseModel &noise)
{
  DeviceNoise d;
  d.terms = 0;
  d.min_sigma_mm = noise.minSigmaMm ();
  for (const auto &term : noise.terms ())
  {
    const auto *poly = dynamic_cast<const texlet::PolynomialSigmaTerm *> (term.get ());
    if (!poly)
      throw pcl::BadArgumentException ("pcl::texlet::gpu::toDeviceNoise: noise term '" + term->name () +
                                       "' has no device form (only 'polynomial' terms)");
    if (d.terms == DeviceNoise::kMaxTerms)
    {
      std::ostringstream msg;
      msg << "pcl::texlet::gpu::toDeviceNoise: the noise model has " << noise.terms ().size () << " terms; the device takes at most "
          << DeviceNoise::kMaxTerms;
      throw pcl::BadArgumentException (msg.str ());
    }
    d.polynomial[d.terms++] = poly->coefficients ();
  }
  return d;
}

} // namespace gpu
} // namespace texlet
} // namespace pcl
