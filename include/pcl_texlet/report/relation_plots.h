/*
 * pcl_texlet multi-sensor: the paper's figures as PNG images drawn by gnuplot (pngcairo):
 * relation histograms with log counts and the inlier boxes (Fig. 10b, 11), and inlier
 * percentage against neighbourhood radius per number of active projectors (Fig. 13).
 */
#pragma once

#include <pcl_texlet/relations/texlet_relations.h>
#include <pcl_texlet/report/gnuplot.h> // gnuplotAvailable

#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{

/** \brief Heat map of \a stats' histogram: normal distance (mm) across, angle (degrees) up,
  * colour log10 of the count (empty bins white), the expected relations' inlier boxes drawn
  * as green rectangles. Written through a temporary file.
  * \throws pcl::IOException if gnuplot fails or the file cannot be written.
  */
void
writeRelationHistogramPng (const RelationStatistics &stats, const std::string &png, const std::string &title);

/** \brief One curve of inlier percentage against radius. */
struct InlierCurve
{
  std::string label;              ///< e.g. "1 projector"
  std::vector<double> radius_px;  ///< x
  std::vector<double> percent;    ///< y
};

/** \brief Inlier percentage (%) against neighbourhood radius (px), one line per curve.
  * \throws pcl::IOException if gnuplot fails or the file cannot be written.
  */
void
writeInlierCurvesPng (const std::vector<InlierCurve> &curves, const std::string &png, const std::string &title,
                      const std::string &y_label = "inlier relations (%)");

} // namespace texlet
} // namespace pcl
