#include <pcl_texlet/noise/noise_model.h>

#include <pcl/exceptions.h>

#include <cmath>
#include <sstream>
#include <typeinfo>

namespace pcl
{
namespace texlet
{

void
NoiseTerm::setSetting (const std::string &setting, double)
{
  throw pcl::BadArgumentException ("noise term '" + name () + "': unknown setting '" + setting + "'");
}

double
PolynomialSigmaTerm::sigmaMm (const PixelContext &ctx) const
{
  return kernels::evaluatePolynomial (c_, ctx.radius_px, ctx.depth_mm);
}

double
PolynomialSigmaTerm::variance (const PixelContext &ctx) const
{
  const double s = sigmaMm (ctx);
  return s > 0.0 ? s * s : 0.0;
}

std::vector<std::string>
PolynomialSigmaTerm::parameterNames () const
{
  return {"p00", "p10", "p01", "p20", "p11", "p02"};
}

std::vector<double>
PolynomialSigmaTerm::parameters () const
{
  return {c_.p00, c_.p10, c_.p01, c_.p20, c_.p11, c_.p02};
}

void
PolynomialSigmaTerm::setParameters (const std::vector<double> &values)
{
  if (values.size () != 6)
  {
    std::ostringstream msg;
    msg << "noise term 'polynomial': expected 6 parameters (p00 p10 p01 p20 p11 p02), got " << values.size ();
    throw pcl::BadArgumentException (msg.str ());
  }
  for (std::size_t i = 0; i < values.size (); ++i)
    if (!std::isfinite (values[i]))
      throw pcl::BadArgumentException ("noise term 'polynomial': parameter " + parameterNames ()[i] + " is not finite");
  c_ = {values[0], values[1], values[2], values[3], values[4], values[5]};
}

NoiseModel::NoiseModel (const NoiseModel &other) : min_sigma_mm_ (other.min_sigma_mm_)
{
  for (const auto &t : other.terms_)
    terms_.push_back (t->clone ());
}

NoiseModel &
NoiseModel::operator= (const NoiseModel &other)
{
  if (this != &other)
  {
    NoiseModel copy (other);
    *this = std::move (copy);
  }
  return *this;
}

NoiseModel
NoiseModel::paper ()
{
  NoiseModel m;
  m.add (PolynomialSigmaTerm ());
  return m;
}

NoiseModel &
NoiseModel::add (const NoiseTerm &term)
{
  terms_.push_back (term.clone ());
  return *this;
}

NoiseTerm::Ptr
NoiseModel::find (const std::string &name) const
{
  for (const auto &t : terms_)
    if (t->name () == name)
      return t;
  return nullptr;
}

NoiseMoments
NoiseModel::moments (const PixelContext &ctx) const
{
  NoiseMoments m;
  if (!(ctx.depth_mm > 0.0) || !std::isfinite (ctx.depth_mm))
  {
    m.sigma_mm = std::nan ("");
    return m;
  }
  double scaled = 0.0, unscaled = 0.0, factor = 1.0, column_rate = 0.0, row_rate = 0.0;
  for (const auto &t : terms_)
  {
    if (t->scaledByFactors ())
      scaled += t->variance (ctx);
    else
      unscaled += t->variance (ctx);
    factor *= t->varianceFactor (ctx);
    const double column = t->columnVariance (ctx);
    m.column_variance_mm2 += column;
    if (column > 0.0)
      column_rate += column / t->columnCorrelationPx (ctx); // 0 for an infinite length
    const double row = t->rowVariance (ctx);
    m.row_variance_mm2 += row;
    if (row > 0.0)
      row_rate += row / t->rowCorrelationPx (ctx);
    const double frame = t->frameVariance (ctx);
    m.frame_variance_mm2 += frame;
    if (row > 0.0)
      m.row_frame_variance_mm2 += frame;
    m.bias_mm += t->bias (ctx);
    const double share = t->windowShare (ctx);
    if (share > m.window_share) // one window: the strongest term's
    {
      m.window_share = share;
      m.window_px = t->windowPx (ctx);
    }
  }
  m.variance_mm2 = scaled * factor + unscaled;
  if (column_rate > 0.0 && m.column_variance_mm2 > 0.0)
    m.column_correlation_px = m.column_variance_mm2 / column_rate;
  if (row_rate > 0.0 && m.row_variance_mm2 > 0.0)
    m.row_correlation_px = m.row_variance_mm2 / row_rate;
  for (const auto &t : terms_)
    t->transformMoments (ctx, m.bias_mm, m.variance_mm2);
  const double s = std::sqrt (m.variance_mm2 + m.sharedVarianceMm2 ());
  m.sigma_mm = s > min_sigma_mm_ ? s : min_sigma_mm_;
  return m;
}

double
NoiseModel::sigmaMm (const PixelContext &ctx) const
{
  return moments (ctx).sigma_mm;
}

double
NoiseModel::biasMm (const PixelContext &ctx) const
{
  return moments (ctx).bias_mm;
}

bool
NoiseModel::movesMean () const
{
  for (const auto &t : terms_)
    if (t->movesMean ())
      return true;
  return false;
}

bool
NoiseModel::isPolynomialOnly (kernels::PolynomialCoefficients &c) const
{
  // The exact type: a subclass may override variance ().
  if (terms_.size () != 1 || typeid (*terms_.front ()) != typeid (PolynomialSigmaTerm))
    return false;
  c = static_cast<const PolynomialSigmaTerm &> (*terms_.front ()).coefficients ();
  return true;
}

bool
NoiseModel::depthSdIsPolynomial (kernels::PolynomialCoefficients &c) const
{
  const NoiseTerm *polynomial = nullptr;
  for (const auto &t : terms_)
    if (!polynomial && typeid (*t) == typeid (PolynomialSigmaTerm))
      polynomial = t.get ();
    else if (t->changesDepthSd ())
      return false;
  if (!polynomial)
    return false;
  c = static_cast<const PolynomialSigmaTerm &> (*polynomial).coefficients ();
  return true;
}

bool
NoiseModel::remove (const std::string &name)
{
  for (auto it = terms_.begin (); it != terms_.end (); ++it)
    if ((*it)->name () == name)
    {
      terms_.erase (it);
      return true;
    }
  return false;
}

void
NoiseModel::setMinSigmaMm (double sigma)
{
  if (!(sigma > 0.0) || !std::isfinite (sigma))
  {
    std::ostringstream msg;
    msg << "NoiseModel::setMinSigmaMm: the sigma floor must be positive and finite (got " << sigma << ")";
    throw pcl::BadArgumentException (msg.str ());
  }
  min_sigma_mm_ = sigma;
}

} // namespace texlet
} // namespace pcl
