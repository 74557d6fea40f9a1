/*
 * pcl_texlet kernels: one texlet of an organised frame, in stages, for every backend.
 *
 * The CPU's pcl::TexletEstimation, the GPU's thread strategy and the host reference of the GPU
 * code run frameTexlet(); the GPU's warp strategy spreads the same stages over the lanes of a
 * warp. The stages read the frame through an accessor, so a pcl::PointCloud and a pitched
 * device cloud run the same code. A frame provides (P: its point type, with x, y, z floats):
 *
 *   int width () const, height () const;
 *   P point (int u, int v) const, point (std::ptrdiff_t index) const;  (index = v * width + u)
 *   bool valid (const P &) const;                whether a point has a depth reading
 *   double sigma (int index, double z) const;    depth SD in metres of the point at a pixel, depth z
 *   CentreNoise centreNoise (int u, int v, double z) const;  the noise model's depth SD there
 *       (metres), the part of its variance a texlet's points share, and its correlation length
 *       across columns
 *   bool hasColour () const;
 *   void addColour (int index, unsigned &r, unsigned &g, unsigned &b) const;  adds a pixel's colour
 *   double varianceScale (int cu, int cv, const TexletResult<S> &) const;  rescale of the
 *       covariances for the texlet's own viewing angle (1: none; the device's answer)
 *
 * (point may return a reference or a value.) The texlet's Philox key is its centre pixel's
 * index, so every backend draws the same numbers.
 */
#pragma once

#include <pcl_texlet/kernels/config.h>
#include <pcl_texlet/kernels/neighbourhood.h>
#include <pcl_texlet/kernels/pixel_disc.h>
#include <pcl_texlet/kernels/texlet_kernel.h>
#include <pcl_texlet/kernels/window_disc_form.h>

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace pcl
{
namespace texlet
{
namespace kernels
{

/** \brief What the stages need besides the frame, fixed for a frame. */
template <typename S>
struct FrameSettings
{
  TexletSettings<S> kernel;        ///< computeTexlet's settings; the threshold is set per texlet
  double fixed_threshold = 0.0;    ///< RANSAC threshold in metres; 0: threshold_sigmas depth SDs
  double threshold_sigmas = 3.0;   ///< of the noise model at the centre pixel and the mean depth
  double min_sigma = 0.0;          ///< metres: the least SD the automatic threshold takes (the model's floor)
  PixelDisc disc;                  ///< the texlet's neighbourhood
  int ring_du[7] = {0, 0, 0, 0, 0, 0, 0}; ///< the ring of normal averaging (hexRingOffsets())
  int ring_dv[7] = {0, 0, 0, 0, 0, 0, 0};
  bool need_sigma = true;          ///< per-point depth SDs, for an uncertainty
  /** Host only: the disc's window tables, for texlets whose disc misses few pixels (null: every
    * texlet's window form by the windows' sums). */
  WindowDiscForms<S> *window_disc_forms = nullptr;
};

/** \brief Scratch of one texlet: x, y, z, sigma, pixel index and mask for disc.size points, and
  * texletWorkSize (disc.size) work values.
  */
template <typename S>
struct TexletScratch
{
  S *x, *y, *z, *sigma, *work;
  int *pixel;
  unsigned char *mask;
};

/** \brief Stores point \a p of pixel \a index as gathered point \a i. */
template <typename S, typename P> PCL_TEXLET_HD void
storePoint (const TexletScratch<S> &ws, int i, const P &p, int index)
{
  ws.x[i] = p.x;
  ws.y[i] = p.y;
  ws.z[i] = p.z;
  ws.pixel[i] = index;
}

/** \brief The valid points of the disc around (cu, cv) into \a ws, in disc order.
  * \param zsum their depths' sum, in that order (the automatic threshold's mean depth)
  * \return how many there are
  */
template <typename S, typename Frame> PCL_TEXLET_HD int
gatherDisc (const Frame &frame, const PixelDisc &disc, int cu, int cv, const TexletScratch<S> &ws, double &zsum)
{
  // The scratch pointers in a local: the stores below cannot then make the compiler reload them.
  const TexletScratch<S> out = ws;
  int count = 0;
  double sum = 0.0;
  forEachDiscPoint (frame, disc, cu, cv, [&] (const auto &p, int index) {
    storePoint (out, count, p, index);
    sum += p.z;
    ++count;
  });
  zsum = sum;
  return count;
}

/** \brief The sum of \a count gathered depths in order: gatherDisc()'s \a zsum, from the points. */
template <typename S> PCL_TEXLET_HD double
depthSum (const S *z, int count)
{
  double sum = 0.0;
  for (int i = 0; i < count; ++i)
    sum += static_cast<float> (z[i]);
  return sum;
}

/** \brief The ring of normal averaging around (cu, cv) into \a nb: points, validity and, when
  * an uncertainty needs them, depth SDs (only its propagation reads them).
  */
template <typename S, typename Frame> PCL_TEXLET_HD void
gatherRing (const Frame &frame, const FrameSettings<S> &fs, int cu, int cv, Neighbourhood<S> &nb)
{
  const int w = frame.width (), h = frame.height ();
  nb.ring_offsets = true;
  for (int k = 0; k < 7; ++k)
  {
    const int u = cu + fs.ring_du[k], v = cv + fs.ring_dv[k];
    nb.ring_du[k] = fs.ring_du[k];
    nb.ring_dv[k] = fs.ring_dv[k];
    nb.ring_valid[k] = false;
    nb.ring[k] = {S (0), S (0), S (0)};
    nb.ring_sigma[k] = S (0);
    if (u < 0 || v < 0 || u >= w || v >= h)
      continue;
    const auto &p = frame.point (u, v);
    if (!frame.valid (p))
      continue;
    nb.ring[k] = {S (p.x), S (p.y), S (p.z)};
    nb.ring_valid[k] = true;
    nb.ring_sigma[k] = fs.need_sigma ? static_cast<S> (frame.sigma (v * w + u, p.z)) : S (0);
  }
}

/** \brief The viewing ray of pixel (cu, cv), scaled to z = 1, into nb.centre_ray: its own
  * point's, or where it has no reading the mean of the rays of the nearest symmetric pair of
  * pixels around it with readings (up to 3 pixels away along a row, a column or a diagonal;
  * exact for a pinhole camera, whose rays are affine in the pixel). None beyond that.
  */
template <typename S, typename Frame> PCL_TEXLET_HD void
gatherCentreRay (const Frame &frame, int cu, int cv, Neighbourhood<S> &nb)
{
  const int w = frame.width (), h = frame.height ();
  nb.has_centre_ray = false;
  const auto &c = frame.point (cu, cv);
  if (frame.valid (c))
  {
    nb.centre_ray = {S (c.x / c.z), S (c.y / c.z), S (1)};
    nb.has_centre_ray = true;
    return;
  }
  const int du[4] = {1, 0, 1, 1}, dv[4] = {0, 1, 1, -1};
  for (int d = 1; d <= 3; ++d)
    for (int k = 0; k < 4; ++k)
    {
      const int ua = cu - d * du[k], va = cv - d * dv[k], ub = cu + d * du[k], vb = cv + d * dv[k];
      if (ua < 0 || ub < 0 || va < 0 || vb < 0 || ua >= w || ub >= w || va >= h || vb >= h)
        continue;
      const auto &a = frame.point (ua, va);
      const auto &b = frame.point (ub, vb);
      if (!frame.valid (a) || !frame.valid (b))
        continue;
      nb.centre_ray = {S (0.5 * (a.x / a.z + b.x / b.z)), S (0.5 * (a.y / a.z + b.y / b.z)), S (1)};
      nb.has_centre_ray = true;
      return;
    }
}

/** \brief Depth SDs of gathered points first, first + stride, ... below \a count. */
template <typename S, typename Frame> PCL_TEXLET_HD void
pointSigmas (const Frame &frame, const TexletScratch<S> &ws, int first, int count, int stride)
{
  for (int i = first; i < count; i += stride)
    ws.sigma[i] = static_cast<S> (frame.sigma (ws.pixel[i], ws.z[i]));
}

/** \brief The RANSAC threshold of a texlet: the fixed one, or threshold_sigmas depth SDs of
  * the noise model at its centre (\a noise: at the centre pixel and the points' mean depth), less
  * the part the disc shares (nb.shared_fraction: it moves the plane, not a point off it): the
  * larger of the unshared part and the part of the shared one that decorrelates across the
  * disc's columns and no plane absorbs; never below fs.min_sigma.
  */
template <typename S> PCL_TEXLET_HD S
ransacThreshold (const FrameSettings<S> &fs, const CentreNoise &noise, const Neighbourhood<S> &nb)
{
  if (fs.fixed_threshold > 0.0)
    return static_cast<S> (fs.fixed_threshold);
  const double rho = static_cast<double> (nb.shared_fraction);
  double own = 1.0;
  if (rho > 0.0)
  {
    const double unshared = 1.0 - rho;
    // Over 2R + 1 columns, offsets correlated by a^|du| are a random walk of step variance
    // 2 (1 - a) rho; less the straight line a plane absorbs, (2R + 1) / 15 of that is left.
    const double decorrelated = rho * 2.0 * (1.0 - static_cast<double> (nb.line_correlation)) *
                                (2.0 * fs.disc.radius + 1.0) / 15.0;
    own = std::sqrt (unshared > decorrelated ? unshared : decorrelated);
  }
  const double sd = noise.sigma * own;
  return static_cast<S> (fs.threshold_sigmas * (sd > fs.min_sigma ? sd : fs.min_sigma));
}

/** \brief The noise the points of a disc share (\a s: the frame's centreNoise ()) into \a nb:
  * shared_fraction within [0, 1], and the correlation of adjacent lines (columns, or rows) with
  * the points' pixel indices \a pixel in a frame of \a width; the window's share (its width
  * rounded to whole pixels, at most kMaxWindowPx), the two shares together at most 1.
  */
template <typename S> PCL_TEXLET_HD void
discSharedNoise (const CentreNoise &s, const int *pixel, int width, Neighbourhood<S> &nb)
{
  nb.shared_fraction = static_cast<S> (s.fraction > 0.0 ? (s.fraction < 1.0 ? s.fraction : 1.0) : 0.0);
  const double L = s.line_correlation_px;
  nb.line_correlation = static_cast<S> (L > 0.0 && L < 1e30 ? std::exp (-1.0 / L) : 1.0);
  nb.pixel = pixel;
  nb.width = width;
  nb.lines_are_rows = s.lines_are_rows;
  nb.window_fraction = static_cast<S> (s.window_fraction > 0.0 ? (s.window_fraction < 1.0 ? s.window_fraction : 1.0) : 0.0);
  nb.window_px = resolvedWindowPx (s.window_px);
  if (nb.window_px == 1 || nb.shared_fraction + nb.window_fraction > S (1)) // a 1 px window shares nothing
    nb.window_fraction = nb.window_px == 1 ? S (0) : S (1) - nb.shared_fraction;
}

/** \brief The inliers' mean colour as PCL's rgba word (alpha 255), 0 for a frame without colour. */
template <typename Frame> PCL_TEXLET_HD std::uint32_t
meanColour (const Frame &frame, const int *pixel, const unsigned char *mask, int count)
{
  if (!frame.hasColour ())
    return 0u;
  unsigned r = 0, g = 0, b = 0, n = 0;
  for (int i = 0; i < count; ++i)
    if (mask[i])
    {
      frame.addColour (pixel[i], r, g, b);
      ++n;
    }
  return (0xffu << 24) | (((r + n / 2) / n) << 16) | (((g + n / 2) / n) << 8) | ((b + n / 2) / n);
}

/** \brief Multiplies both covariances by \a f (the frame's varianceScale()). */
template <typename S> PCL_TEXLET_HD void
scaleCovariances (double f, TexletResult<S> &r)
{
  if (f == 1.0)
    return;
  for (int i = 0; i < 6; ++i)
    r.cov_p[i] *= f;
  for (int i = 0; i < 3; ++i)
    r.cov_n[i] *= f;
}

/** \brief Writes a texlet into an output point with pcl::Texlet's field names (pcl::Texlet or
  * the GPU's DeviceTexlet); the fields it does not name (the padding) keep their values.
  */
template <typename S, typename Out> PCL_TEXLET_HD void
writeTexlet (const TexletResult<S> &r, std::uint32_t rgba, std::uint32_t centre, Out &out)
{
  out.x = static_cast<float> (r.P.x);
  out.y = static_cast<float> (r.P.y);
  out.z = static_cast<float> (r.P.z);
  out.normal_x = static_cast<float> (r.N.x);
  out.normal_y = static_cast<float> (r.N.y);
  out.normal_z = static_cast<float> (r.N.z);
  out.rgba = rgba;
  out.curvature = static_cast<float> (r.curvature);
  out.radius = static_cast<float> (r.radius);
  out.support = static_cast<std::uint32_t> (r.support);
  out.cov_p_xx = static_cast<float> (r.cov_p[0]);
  out.cov_p_xy = static_cast<float> (r.cov_p[1]);
  out.cov_p_xz = static_cast<float> (r.cov_p[2]);
  out.cov_p_yy = static_cast<float> (r.cov_p[3]);
  out.cov_p_yz = static_cast<float> (r.cov_p[4]);
  out.cov_p_zz = static_cast<float> (r.cov_p[5]);
  out.cov_n_11 = static_cast<float> (r.cov_n[0]);
  out.cov_n_12 = static_cast<float> (r.cov_n[1]);
  out.cov_n_22 = static_cast<float> (r.cov_n[2]);
  out.pixel_index = centre;
}

/** \brief Writes a texlet that could not be made: NaN, no colour, support 0. */
template <typename Out> PCL_TEXLET_HD void
writeFailedTexlet (std::uint32_t centre, Out &out)
{
  TexletResult<float> r;
  r.P = r.N = {NAN, NAN, NAN};
  r.curvature = r.radius = NAN;
  r.support = 0;
  fillNaN (r.cov_p, 6);
  fillNaN (r.cov_n, 3);
  writeTexlet (r, 0u, centre, out);
}

/** \brief computeTexlet() as the kernel of frameTexlet(), inlined. */
struct InlineTexletKernel
{
  template <typename S> PCL_TEXLET_HD void
  operator() (const Neighbourhood<S> &nb, const TexletSettings<S> &st, std::uint32_t texlet, unsigned char *mask,
              S *work, TexletResult<S> &out) const
  {
    computeTexlet (nb, st, texlet, mask, work, out);
  }
};

/** \brief The texlet centred on pixel (cu, cv) of \a frame into \a out: the disc's valid points
  * in disc order, the ring, the centre ray, per-point depth SDs, the threshold, then \a kernel
  * (computeTexlet() or a build of it) keyed by the centre pixel's index, the frame's variance
  * rescale and the inliers' mean colour. \return false (and a failed texlet) where none could be made
  */
template <typename S, typename Frame, typename Kernel, typename Out> PCL_TEXLET_HD bool
frameTexlet (const Frame &frame, const FrameSettings<S> &fs, int cu, int cv, const TexletScratch<S> &ws,
             const Kernel &kernel, Out &out)
{
  const std::uint32_t centre = static_cast<std::uint32_t> (cv) * static_cast<std::uint32_t> (frame.width ()) + cu;
  double zsum = 0.0;
  const int count = gatherDisc (frame, fs.disc, cu, cv, ws, zsum);
  if (count == 0)
  {
    writeFailedTexlet (centre, out);
    return false;
  }
  Neighbourhood<S> nb;
  nb.x = ws.x;
  nb.y = ws.y;
  nb.z = ws.z;
  nb.count = count;
  gatherRing (frame, fs, cu, cv, nb);
  gatherCentreRay (frame, cu, cv, nb);
  if (fs.need_sigma)
  {
    pointSigmas (frame, ws, 0, count, 1);
    nb.sigma = ws.sigma;
  }
  const CentreNoise noise = frame.centreNoise (cu, cv, zsum / count);
  discSharedNoise (noise, ws.pixel, frame.width (), nb);
#if !defined(__CUDA_ARCH__)
  // The window's form from tables where the disc misses few pixels (window_disc_form.h).
  if (fs.window_disc_forms && nb.window_fraction > S (0) && count + kMaxWindowDiscGaps >= fs.disc.size)
  {
    nb.window_disc = fs.window_disc_forms->of (nb.window_px);
    if (nb.window_disc && count < fs.disc.size)
    {
      nb.disc_offset = fs.window_disc_forms->offsetsOf (ws.pixel, count, cu, cv, frame.width (), frame.height ());
      if (!nb.disc_offset)
        nb.window_disc = nullptr;
    }
  }
#endif
  TexletSettings<S> st = fs.kernel;
  st.threshold = ransacThreshold (fs, noise, nb);

  TexletResult<S> r;
  kernel (nb, st, centre, ws.mask, ws.work, r);
  if (!r.ok)
  {
    writeFailedTexlet (centre, out);
    return false;
  }
  if (fs.need_sigma)
    scaleCovariances (frame.varianceScale (cu, cv, r), r);
  writeTexlet (r, meanColour (frame, ws.pixel, ws.mask, count), centre, out);
  return true;
}

} // namespace kernels
} // namespace texlet
} // namespace pcl
