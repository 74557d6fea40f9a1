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
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3f> eig (t.covarianceP ());
    for (int i = 0; i < 3; ++i)
    {
      const float sd = std::sqrt (std::max (0.0f, eig.eigenvalues ()[i]));
      const Eigen::Vector3f half = static_cast<float> (scales.sigma_p) * sd * eig.eigenvectors ().col (i);
      g.line (t.getVector3fMap () - half, t.getVector3fMap () + half, red);
    }
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
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2f> eig (t.covarianceN ());
    const Eigen::Matrix<float, 3, 2> tf = t.tangentFrame ();
    for (int i = 0; i < 2; ++i)
    {
      const float sd = std::sqrt (std::max (0.0f, eig.eigenvalues ()[i]));
      // An angular deviation of sd radians moves the tip by sd * length along that tangent.
      const Eigen::Vector3f half = static_cast<float> (scales.sigma_n) * sd * length * (tf * eig.eigenvectors ().col (i));
      g.line (tip - half, tip + half, green);
    }
  }
  return g.actor (2.0f);
}

} // namespace pcl_texlet_viewer
