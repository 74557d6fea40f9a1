/*
 * pcl_texlet model lab, steps 3, 5 and 6: a session from a starting model to a refitted one,
 * and its report: report.json, report.html (self-contained, plots embedded), the PNG plots
 * (gnuplot, pngcairo) and model.yaml.
 */
#pragma once

#include <pcl_texlet/lab/disparity_lattice.h>
#include <pcl_texlet/lab/model_lab.h>
#include <pcl_texlet/lab/residual_diagnostics.h>

#include <string>
#include <vector>

namespace pcl
{
namespace texlet
{
namespace lab
{

/** \brief One effect added to the model, and the metrics after it (all data, refitted). */
struct LabStep
{
  std::string added;
  LabMetrics metrics;
  NoiseModel model;
  bool from_auto = false;   ///< chosen by --auto (the best significant candidate)
  ResidualDiagnostics unexplained; ///< the structure the model leaves after this step
};

/** \brief A whole lab session. */
struct LabSession
{
  std::string start_name;               ///< "paper" or the YAML file
  NoiseModel start;                     ///< the model as given
  LabMetrics start_metrics;             ///< of the model as given, all data
  std::vector<Candidate> candidates;    ///< ranked against the starting model
  std::vector<LabStep> steps;           ///< effects added, in order
  NoiseModel final_model;               ///< the last step's model, or the start refitted
  ResidualDiagnostics start_unexplained; ///< the structure the model as given leaves
  ResidualDiagnostics unexplained;      ///< the structure the final model leaves (report.json "unexplained")
  std::vector<std::string> notes;       ///< what the lab could not do, and why
  std::size_t skipped_frames = 0;       ///< frames the caller could not read and skipped (report.json)
  DisparityLattice lattice;             ///< the depth values' disparity lattice, beside camera.yaml's
};

/** \brief Runs a session: rank the candidates of \a start, add \a add in order, then up to
  * \a auto_count best significant candidates in turn (re-ranking after each).
  * \throws pcl::BadArgumentException for an unknown effect, or one already in the model.
  */
LabSession
runLabSession (const ModelLab &lab, const NoiseModel &start, const std::string &start_name,
               const std::vector<std::string> &add, int auto_count);

/** \brief report.json text (keys: model, metrics, unexplained, start_unexplained, candidates,
  * steps, skipped_frames, notes, disparity_lattice).
  */
std::string
labReportJson (const LabSession &session);

/** \brief Writes report.json, report.html, the PNGs and model.yaml into \a folder (created if
  * missing; each file through a temporary file renamed when complete).
  * \throws pcl::IOException if the folder cannot be written or gnuplot fails.
  */
void
writeLabReport (const ModelLab &lab, const LabSession &session, const std::string &folder);

} // namespace lab
} // namespace texlet
} // namespace pcl
