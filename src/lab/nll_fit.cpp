#include "nll_fit.h"

#include "likelihood.h"
#include "quantisation_lattice.h"
#include "setting_combinations.h"
#include "spatial_correlation_fit.h"

#include <pcl_texlet/noise/effect_registry.h>
#include <pcl_texlet/noise/noise_terms.h>

#include <ceres/first_order_function.h>
#include <ceres/gradient_problem.h>
#include <ceres/gradient_problem_solver.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace pcl
{
namespace texlet
{
namespace lab
{
namespace detail
{

namespace
{

/** Where a model's fitted parameters live: (term index, parameter index), with a scale. */
struct ParameterMap
{
  std::vector<std::pair<std::size_t, std::size_t>> where;
  std::vector<double> scale;
};

/** Whether \a term rounds on the lattice of step \a data_step_px (0: none) that the recordings'
  * depths show (quantisation_lattice.h): the data fix that step, and a gradient could not fit it
  * (the likelihood jumps wherever a level moves past a pixel's disparity). */
bool
onDataLattice (const NoiseTerm &term, double data_step_px)
{
  return term.quantises () && data_step_px > 0 && !term.parameters ().empty () &&
         std::fabs (term.parameters ()[0] - data_step_px) <= 1e-9 * data_step_px;
}

/** The step of the lattice \a lattice of the recordings' depths, 0 when they show camera.yaml's or none. */
double
dataLatticeStepPx (const QuantisationLattice &lattice, const std::vector<RecordingMeasurement::ConstPtr> &recs)
{
  if (recs.empty () || lattice.constant_mm <= 0)
    return 0;
  return lattice.stepPx (recs.front ()->fb (), recs.front ()->camera.disparity_subpixel);
}

/** The parameters a fit changes: every term's but a linear bias term's, a parameter of the
  * steady mean and a rounding's on the data's lattice (\a data_step_px, onDataLattice()), or only
  * \a only_term's. */
ParameterMap
parameterMap (const NoiseModel &m, int only_term = -1, double data_step_px = 0)
{
  ParameterMap pm;
  for (std::size_t t = 0; t < m.terms ().size (); ++t)
  {
    const auto &term = m.terms ()[t];
    // A linear bias term is fitted by least squares, not here; a term of the neighbours'
    // correlation changes no pixel's likelihood (spatial_correlation_fit.h).
    if (term->linearBiasSupport () > 0 || (only_term >= 0 && static_cast<int> (t) != only_term) ||
        fittedToNeighbourPairs (term->name ()) || onDataLattice (*term, data_step_px))
      continue;
    const auto values = term->parameters ();
    for (std::size_t k = 0; k < values.size (); ++k)
    {
      if (term->fittedToMeans (k)) // by least squares with the surfaces (staticFit)
        continue;
      pm.where.emplace_back (t, k);
      pm.scale.push_back (std::max (std::fabs (values[k]), term->typicalScale (k)));
    }
  }
  return pm;
}

/** Sets the parameters of \a pm to \a x times their scales, each at least its lowest value (the
  * term reads one below as that, so the likelihood is flat there and the model the same). */
void
setScaled (NoiseModel &m, const ParameterMap &pm, const double *x)
{
  std::size_t k = 0;
  while (k < pm.where.size ())
  {
    const std::size_t t = pm.where[k].first;
    const NoiseTerm &term = *m.terms ()[t];
    auto values = term.parameters ();
    for (; k < pm.where.size () && pm.where[k].first == t; ++k)
      values[pm.where[k].second] = std::max (x[k] * pm.scale[k], term.lowestValue (pm.where[k].second));
    m.terms ()[t]->setParameters (values);
  }
}

/** The temporal NLL per sample of the model with the parameters of \a pm, for Ceres. */
class NllFunction : public ceres::FirstOrderFunction
{
public:
  NllFunction (const NoiseModel &model, const ParameterMap &pm, const ModelLab::Data &d, const StaticState &s,
               double samples)
    : model_ (model), pm_ (pm), d_ (d), s_ (s), samples_ (samples)
  {
  }

  bool
  Evaluate (const double *x, double *cost, double *gradient) const override
  {
    const int n = NumParameters ();
    if (!value (x, cost))
      return false;
    if (gradient)
    {
      std::vector<double> xx (x, x + n);
      for (int k = 0; k < n; ++k)
      {
        const double h = 1e-5 * std::max (1.0, std::fabs (x[k]));
        double fp = 0, fm = 0;
        xx[k] = x[k] + h;
        const bool okp = value (xx.data (), &fp);
        xx[k] = x[k] - h;
        const bool okm = value (xx.data (), &fm);
        xx[k] = x[k];
        if (!okp || !okm)
          return false;
        gradient[k] = (fp - fm) / (2 * h);
      }
    }
    return true;
  }

  int
  NumParameters () const override { return static_cast<int> (pm_.where.size ()); }

private:
  bool
  value (const double *x, double *cost) const
  {
    setScaled (model_, pm_, x);
    const ModelView mv (model_);
    binMoments (mv, mv.quantised ? d_.qbins : d_.bins, s_);
    // Variance parameters are fitted on the temporal contrasts only (as REML does): the
    // pixels' means are for the surfaces and the bias terms, so that an unmodelled bias is not
    // taken for noise.
    const double L = objective (mv, d_, s_, false) / samples_;
    if (!std::isfinite (L))
      return false;
    *cost = L;
    return true;
  }

  mutable NoiseModel model_;
  const ParameterMap &pm_;
  const ModelLab::Data &d_;
  // The caller's state, copied once: an evaluation rewrites only its per-bin moments, and a copy
  // per evaluation would move the per-pixel biases too (docs/model_lab.md section 9).
  mutable StaticState s_;
  double samples_;
};

/** Starting values for a term that was just added (its neutral values sit on a saddle): the
  * term's own, some from the recordings and the disparity lattice \a lattice their depths show.
  */
void
startValues (NoiseTerm &term, const std::vector<RecordingMeasurement::ConstPtr> &recs,
             const QuantisationLattice &lattice)
{
  effects::LabStart facts;
  facts.image_width = recs.front ()->width;
  facts.image_height = recs.front ()->height;
  facts.disparity_step_px = recs.front ()->camera.disparity_subpixel;
  if (term.quantises () && lattice.constant_mm > 0)
  {
    facts.lattice_step_px = lattice.stepPx (recs.front ()->fb (), facts.disparity_step_px);
    facts.lattice_phase = lattice.phase;
  }
  term.setLabStart (facts);
}

/** One Ceres run over the parameters of \a pm, from the model's current values. */
void
ceresRun (NoiseModel &model, const ParameterMap &pm, const ModelLab::Data &d, const StaticState &s,
          const LabSettings &settings)
{
  if (pm.where.empty ())
    return;
  std::vector<double> x (pm.where.size ());
  for (std::size_t k = 0; k < x.size (); ++k)
    x[k] = model.terms ()[pm.where[k].first]->parameters ()[pm.where[k].second] / pm.scale[k];
  ceres::GradientProblem problem (new NllFunction (model, pm, d, s, d.samples));
  ceres::GradientProblemSolver::Options options;
  options.line_search_direction_type = ceres::LBFGS;
  options.max_num_iterations = settings.max_lbfgs_iterations;
  options.function_tolerance = 1e-10;
  options.gradient_tolerance = 1e-9;
  options.logging_type = ceres::SILENT;
  ceres::GradientProblemSolver::Summary summary;
  const std::vector<double> x0 = x;
  ceres::Solve (options, problem, x.data (), &summary);
  bool finite = true;
  for (double v : x)
    finite = finite && std::isfinite (v);
  setScaled (model, pm, finite ? x.data () : x0.data ());
}

/** \a model with the effect \a name added at its starting values. */
NoiseModel
withTerm (const NoiseModel &model, const std::string &name, const std::vector<RecordingMeasurement::ConstPtr> &recs,
          const QuantisationLattice &lattice)
{
  NoiseModel m (model);
  NoiseTerm::Ptr term = makeNoiseTerm (name);
  startValues (*term, recs, lattice);
  m.add (*term);
  return m;
}

} // namespace

double
fitObjective (NoiseModel &model, const ModelLab::Data &d, const std::vector<RecordingMeasurement::ConstPtr> &recs,
              StaticState &s, GridFit grid_fit)
{
  const ModelView mv (model);
  staticFit (mv, d, recs, grid_fit, s);
  if (mv.grid && !s.grid.empty ())
  {
    // Settings first: setting one resets the term's parameters.
    const NoiseTerm::Ptr grid = model.find (mv.grid->name ());
    for (const auto &kv : s.grid_settings)
      grid->setSetting (kv.first, kv.second);
    grid->setParameters (s.grid);
  }
  for (std::size_t j = 0; j < s.means.size (); ++j)
  {
    const NoiseTerm::Ptr term = model.find (mv.means[j].first);
    std::vector<double> values = term->parameters ();
    values[mv.means[j].second] = s.means[j];
    term->setParameters (values);
  }
  return objective (ModelView (model), d, s) / d.samples;
}

NoiseModel
fitOn (const NoiseModel &start, const ModelLab::Data &d, const std::vector<RecordingMeasurement::ConstPtr> &recs,
       const LabSettings &settings, int new_term, double nested_objective)
{
  NoiseModel model (start);
  const double data_step_px = dataLatticeStepPx (d.lattice, recs);
  const ParameterMap pm = parameterMap (model, -1, data_step_px);
  // A rounding, a linear bias term or a steady mean's parameter: the static fit changes with the rest.
  const bool has_static = ModelView (model).hasStaticFit ();
  // A new grid term's shape along depth is chosen in the first static fit, its nodes in every
  // one: the shape's score is the static NLL, which the variances fitted next hardly move
  // (the grid is a bias), and each shape tried is one more solve (docs/model_lab.md section 9).
  GridFit grid_fit = new_term >= 0 && model.terms ()[new_term]->linearBiasSupport () > 0 ? GridFit::nodes_and_shape
                                                                                        : GridFit::nodes;
  auto shapeChosen = [&] {
    if (grid_fit == GridFit::nodes_and_shape)
      grid_fit = GridFit::nodes;
  };
  const int outer = has_static ? std::max (1, settings.outer_iterations) : std::min (2, std::max (1, settings.outer_iterations));
  if (new_term >= 0)
  {
    const ParameterMap own = parameterMap (model, new_term, data_step_px);
    const auto &term = model.terms ()[new_term];
    if (!own.where.empty () || !term->formSearch ().empty ())
    {
      // Scan the scale of the term's first parameter in each of its forms, then fit its
      // parameters alone in the best; a step the data fix is neither scanned nor fitted.
      const std::vector<double> initial = term->parameters ();
      const std::vector<double> scales = own.where.empty () || own.where.front ().second != 0
                                             ? std::vector<double>{1.0}
                                             : std::vector<double>{0.1, 0.3, 1.0, 3.0};
      double best = std::numeric_limits<double>::infinity ();
      std::vector<double> best_values = initial;
      SettingCombination best_form;
      forEachSettingCombination (term->formSearch (), [&] (const SettingCombination &form) {
        for (const auto &kv : form)
          term->setSetting (kv.first, kv.second);
        for (double f : scales)
        {
          std::vector<double> v = initial;
          v[0] *= f;
          term->setParameters (v);
          StaticState s;
          const double L = fitObjective (model, d, recs, s, grid_fit);
          if (L < best)
            best = L, best_values = v, best_form = form;
        }
      });
      for (const auto &kv : best_form)
        term->setSetting (kv.first, kv.second);
      term->setParameters (best_values);
      StaticState s;
      fitObjective (model, d, recs, s, grid_fit);
      shapeChosen ();
      ceresRun (model, own, d, s, settings);
    }
  }
  for (int it = 0; it < outer; ++it)
  {
    StaticState s;
    fitObjective (model, d, recs, s, grid_fit);
    shapeChosen ();
    ceresRun (model, pm, d, s, settings);
  }
  StaticState s;
  const double L = fitObjective (model, d, recs, s, grid_fit);
  if (new_term >= 0 && std::isfinite (nested_objective) && !(L <= nested_objective))
  {
    // Worse than without the term: the fit is stuck; the nested model with the term neutral.
    NoiseModel nested (start);
    const std::string name = nested.terms ()[new_term]->name ();
    const NoiseTerm::Ptr neutral = makeNoiseTerm (name);
    nested.terms ()[new_term]->setParameters (neutral->parameters ());
    return nested;
  }
  return model;
}

NoiseModel
fitWithEffect (const NoiseModel &fitted, const NoiseModel &given, const std::string &name, const ModelLab::Data &d,
               const std::vector<RecordingMeasurement::ConstPtr> &recs, const LabSettings &settings,
               double nested_objective, int fits)
{
  const int added = static_cast<int> (fitted.terms ().size ());
  const bool two_fits = effectInfo (name).quantises && given.terms ().size () == fitted.terms ().size ();
  if (fits == 1 && two_fits)
    return fitOn (withTerm (given, name, recs, d.lattice), d, recs, settings, added, nested_objective);
  NoiseModel m = fitOn (withTerm (fitted, name, recs, d.lattice), d, recs, settings, added, nested_objective);
  if (fits >= 0 || !two_fits)
    return m;
  NoiseModel alt = fitOn (withTerm (given, name, recs, d.lattice), d, recs, settings, added, nested_objective);
  NoiseModel m_copy (m), alt_copy (alt);
  StaticState sm, sa;
  return fitObjective (alt_copy, d, recs, sa) < fitObjective (m_copy, d, recs, sm) ? alt : m;
}

double
scoreOn (const NoiseModel &model, const ModelLab::Data &d, const std::vector<RecordingMeasurement::ConstPtr> &recs)
{
  const ModelView mv (model);
  StaticState s;
  staticFit (mv, d, recs, GridFit::none, s);
  return objective (mv, d, s) / d.samples;
}

} // namespace detail
} // namespace lab
} // namespace texlet
} // namespace pcl
