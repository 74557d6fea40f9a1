#include "texlet_layers.h"

#include <Eigen/Eigenvalues>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace pcl_texlet_viewer
{

namespace
{

/** Points, cells and per-cell colours, turned into an unlit actor at the end. */
struct Geometry
{
  vtkSmartPointer<vtkPoints> points = vtkSmartPointer<vtkPoints>::New ();
  vtkSmartPointer<vtkCellArray> cells = vtkSmartPointer<vtkCellArray>::New ();
  vtkSmartPointer<vtkUnsignedCharArray> colours = vtkSmartPointer<vtkUnsignedCharArray>::New ();
  bool polygons;

  explicit Geometry (bool polys) : polygons (polys) { colours->SetNumberOfComponents (3); }

  void
  line (const Eigen::Vector3f &a, const Eigen::Vector3f &b, const unsigned char rgb[3])
  {
    const vtkIdType ids[2] = {points->InsertNextPoint (a.data ()), points->InsertNextPoint (b.data ())};
    cells->InsertNextCell (2, ids);
    colours->InsertNextTypedTuple (rgb);
  }

  vtkSmartPointer<vtkActor>
  actor (float line_width = 1.0f) const
  {
    auto poly = vtkSmartPointer<vtkPolyData>::New ();
    poly->SetPoints (points);
    if (polygons)
      poly->SetPolys (cells);
    else
      poly->SetLines (cells);
    poly->GetCellData ()->SetScalars (colours);
    auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New ();
    mapper->SetInputData (poly);
    mapper->SetColorModeToDirectScalars ();
    mapper->SetScalarModeToUseCellData ();
    auto a = vtkSmartPointer<vtkActor>::New ();
    a->SetMapper (mapper);
    a->GetProperty ()->LightingOff ();
    a->GetProperty ()->SetLineWidth (line_width);
    return a;
  }
};

bool
valid (const pcl::Texlet &t)
{
  return std::isfinite (t.x) && std::isfinite (t.normal_x) && std::isfinite (t.radius);
}

/** The median texlet radius: drawn sizes follow it, so that the few texlets spread across a
  * depth step do not draw metre-long lines.
  */
float
typicalRadius (const pcl::PointCloud<pcl::Texlet> &texlets)
{
  std::vector<float> r;
  for (const auto &t : texlets)
    if (valid (t))
      r.push_back (t.radius);
  if (r.empty ())
    return 0.0f;
  std::nth_element (r.begin (), r.begin () + r.size () / 2, r.end ());
  return r[r.size () / 2];
}

/** Lines through \a centre along each principal axis of the covariance \a cov, each way as long
  * as \a half (scale * SD, unit eigenvector) says (in 3-D).
  */
template <typename Covariance, typename Half> void
sdAxes (Geometry &g, const Eigen::Vector3f &centre, const Covariance &cov, float scale, Half half,
        const unsigned char rgb[3])
{
  const Eigen::SelfAdjointEigenSolver<Covariance> eig (cov);
  for (int i = 0; i < Covariance::RowsAtCompileTime; ++i)
  {
    const float sd = std::sqrt (std::max (0.0f, eig.eigenvalues ()[i]));
    const Eigen::Vector3f h = half (scale * sd, eig.eigenvectors ().col (i));
    g.line (centre - h, centre + h, rgb);
  }
}

} // namespace

vtkSmartPointer<vtkActor>
makeDiscActor (const pcl::PointCloud<pcl::Texlet> &texlets, const LayerScales &scales)
{
  constexpr int kSides = 12;
  Geometry g (true);
  const float cap = 2.0f * typicalRadius (texlets);
  for (const auto &t : texlets)
  {
    if (!valid (t))
      continue;
    const Eigen::Matrix<float, 3, 2> tf = t.tangentFrame ();
    const Eigen::Vector3f p = t.getVector3fMap ();
    const float r = static_cast<float> (scales.disc) * std::min (t.radius, cap);
    vtkIdType ids[kSides];
    for (int k = 0; k < kSides; ++k)
    {
      const float a = 2.0f * static_cast<float> (M_PI) * k / kSides;
      const Eigen::Vector3f q = p + r * (std::cos (a) * tf.col (0) + std::sin (a) * tf.col (1));
      ids[k] = g.points->InsertNextPoint (q.data ());
    }
    g.cells->InsertNextCell (kSides, ids);
    const unsigned char rgb[3] = {t.r, t.g, t.b};
    g.colours->InsertNextTypedTuple (rgb);
  }
  return g.actor ();
}

vtkSmartPointer<vtkActor>
makeNormalActor (const pcl::PointCloud<pcl::Texlet> &texlets, const LayerScales &scales)
{
  Geometry g (false);
  const unsigned char white[3] = {230, 230, 230};
  const float length = static_cast<float> (scales.normal) * typicalRadius (texlets);
  for (const auto &t : texlets)
    if (valid (t))
      g.line (t.getVector3fMap (), t.getVector3fMap () + length * t.getNormalVector3fMap (), white);
  return g.actor ();
}

vtkSmartPointer<vtkActor>
makeSigmaPActor (const pcl::PointCloud<pcl::Texlet> &texlets, const LayerScales &scales)
{
  Geometry g (false);
  const unsigned char red[3] = {255, 40, 40};
  for (const auto &t : texlets)
  {
    if (!valid (t) || !std::isfinite (t.cov_p_xx))
      continue;
    sdAxes (g, t.getVector3fMap (), t.covarianceP (), static_cast<float> (scales.sigma_p),
            [] (float scaled_sd, const Eigen::Vector3f &axis) -> Eigen::Vector3f { return scaled_sd * axis; }, red);
  }
  return g.actor (2.0f);
}

vtkSmartPointer<vtkActor>
makeSigmaNActor (const pcl::PointCloud<pcl::Texlet> &texlets, const LayerScales &scales)
{
  Geometry g (false);
  const unsigned char green[3] = {40, 255, 40};
  const float length = static_cast<float> (scales.normal) * typicalRadius (texlets);
  for (const auto &t : texlets)
  {
    if (!valid (t) || !std::isfinite (t.cov_n_11))
      continue;
    const Eigen::Vector3f tip = t.getVector3fMap () + length * t.getNormalVector3fMap ();
    const Eigen::Matrix<float, 3, 2> tf = t.tangentFrame ();
    // An angular deviation of sd radians moves the tip by sd * length along that tangent.
    sdAxes (g, tip, t.covarianceN (), static_cast<float> (scales.sigma_n),
            [&] (float scaled_sd, const Eigen::Vector2f &axis) -> Eigen::Vector3f { return scaled_sd * length * (tf * axis); },
            green);
  }
  return g.actor (2.0f);
}

} // namespace pcl_texlet_viewer
