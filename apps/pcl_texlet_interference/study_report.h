/*
 * pcl_texlet_interference: the study's outputs: inliers.json and a self-contained report.html.
 */
#pragma once

#include "interference_study.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace pcl_texlet_interference
{

/** \brief A finished cell and the file name of its histogram image (empty: none drawn). */
struct CellResult
{
  pcl::texlet::InterferenceCell cell;
  std::string histogram_png;
  double seconds = 0.0;
};

/** \brief The peak of each point relation (not the ranges) within 7 mm and 20 degrees. */
nlohmann::json
peaksJson (const pcl::texlet::RelationStatistics &stats);

/** \brief inliers.json: the setup, the object, and per cell the counts, percentages, peaks and
  * face statistics.
  */
nlohmann::json
studyJson (const nlohmann::json &setup, const pcl::texlet::KnownObject &object, const std::vector<CellResult> &cells);

/** \brief report.html with every image of \a folder named in \a json embedded as base64. */
std::string
studyHtml (const nlohmann::json &json, const std::string &folder, const std::string &curves_png);

} // namespace pcl_texlet_interference
