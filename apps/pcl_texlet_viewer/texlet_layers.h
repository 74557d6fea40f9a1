/*
 * pcl_texlet_viewer: VTK geometry for the texlet layers (discs, normals, uncertainty axes).
 */
#pragma once

#include <pcl_texlet/features/point_types.h>

#include <pcl/point_cloud.h>

#include <vtkActor.h>
#include <vtkSmartPointer.h>

namespace pcl_texlet_viewer
{

/** \brief How big the drawn things are. */
struct LayerScales
{
  double disc = 0.6;          ///< disc radius as a fraction of the texlet's radius (capped at twice the median)
  double normal = 1.5;        ///< normal length as a multiple of the frame's median texlet radius
  double sigma_p = 50.0;      ///< Sigma_P axes: this many SDs (mm become visible)
  double sigma_n = 10.0;      ///< Sigma_N axes at the normal's tip: this many SDs (radians x normal length)
};

/** \brief Texlets as flat discs in their tangent planes, filled with their mean colour and
  * drawn unlit, so the image shows the exact colours.
  */
vtkSmartPointer<vtkActor>
makeDiscActor (const pcl::PointCloud<pcl::Texlet> &texlets, const LayerScales &scales);

/** \brief Normals as short lines from each centre. */
vtkSmartPointer<vtkActor>
makeNormalActor (const pcl::PointCloud<pcl::Texlet> &texlets, const LayerScales &scales);

/** \brief Principal axes of Sigma_P (red) at each centre, as in the paper's Fig. 2c. */
vtkSmartPointer<vtkActor>
makeSigmaPActor (const pcl::PointCloud<pcl::Texlet> &texlets, const LayerScales &scales);

/** \brief Principal axes of Sigma_N (green) at each normal's tip, as in the paper's Fig. 2c. */
vtkSmartPointer<vtkActor>
makeSigmaNActor (const pcl::PointCloud<pcl::Texlet> &texlets, const LayerScales &scales);

} // namespace pcl_texlet_viewer
