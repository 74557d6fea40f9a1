#include <pcl_texlet/noise/effect_adapter.h>
#include <pcl_texlet/noise/effect_registry.h>
#include <pcl_texlet/noise/effects/axial_quadratic.h>
#include <pcl_texlet/noise/effects/covariate_intensity.h>
#include <pcl_texlet/noise/effects/depth_distortion.h>
#include <pcl_texlet/noise/effects/disparity_quantization.h>
#include <pcl_texlet/noise/effects/incidence_angle.h>
#include <pcl_texlet/noise/effects/interference.h>
#include <pcl_texlet/noise/effects/intrinsics.h>
#include <pcl_texlet/noise/effects/lateral_noise.h>
#include <pcl_texlet/noise/effects/radial.h>
#include <pcl_texlet/noise/effects/row_bands.h>
#include <pcl_texlet/noise/effects/spatial_correlation.h>
#include <pcl_texlet/noise/effects/temporal_drift.h>
#include <pcl_texlet/noise/effects/vertical_stripes.h>

#include <pcl/exceptions.h>

namespace pcl
{
namespace texlet
{

void
detail::throwBadArgument (const std::string &message)
{
  throw pcl::BadArgumentException (message);
}

const EffectRegistry &
EffectRegistry::vocabulary ()
{
  // The vocabulary's order (docs/sensor_model.md): it is the order of the catalogue, of the
  // lab's candidates and of the simulator's SD factors.
  static const EffectRegistry registry = [] {
    EffectRegistry r;
    r.add<effects::AxialQuadratic> ();
    r.add<effects::Radial> ();
    r.add<effects::DisparityQuantization> ();
    r.add<effects::IncidenceAngle> ();
    r.add<effects::VerticalStripes> ();
    r.add<effects::DepthDistortion> ();
    r.add<effects::Interference> ();
    r.add<effects::TemporalDrift> ();
    r.add<effects::LateralNoise> ();
    r.add<effects::Intrinsics> ();
    // Terms built from the data, named by the structure they take off the residuals.
    r.add<effects::CovariateIntensity> ();
    r.add<effects::RowBands> ();
    r.add<effects::SpatialCorrelation> ();
    return r;
  }();
  return registry;
}

void
EffectRegistry::addEntry (Entry entry)
{
  if (find (entry.info.name) >= 0)
    throw pcl::BadArgumentException ("effect registry: the effect '" + entry.info.name + "' is registered twice");
  entries_.push_back (std::move (entry));
}

int
EffectRegistry::find (const std::string &name) const
{
  for (std::size_t i = 0; i < entries_.size (); ++i)
    if (entries_[i].info.name == name)
      return static_cast<int> (i);
  return -1;
}

std::string
EffectRegistry::knownNames () const
{
  std::string names;
  for (const auto &e : entries_)
    names += (names.empty () ? "" : ", ") + e.info.name;
  return names;
}

std::size_t
EffectRegistry::index (const std::string &name) const
{
  const int i = find (name);
  if (i < 0)
    throw pcl::BadArgumentException ("unknown effect '" + name + "' (known: " + knownNames () + ")");
  return static_cast<std::size_t> (i);
}

NoiseTerm::Ptr
EffectRegistry::makeTerm (std::size_t index) const
{
  const Entry &e = entries_.at (index);
  return e.term ? e.term () : nullptr;
}

GenerativeEffect::ConstPtr
EffectRegistry::generative (std::size_t index, const std::vector<double> &values) const
{
  const Entry &e = entries_.at (index);
  return e.generative ? e.generative (values) : nullptr;
}

const std::vector<EffectInfo> &
effectCatalogue ()
{
  static const std::vector<EffectInfo> catalogue = [] {
    const EffectRegistry &r = EffectRegistry::vocabulary ();
    std::vector<EffectInfo> c;
    for (std::size_t i = 0; i < r.size (); ++i)
      c.push_back (r.info (i));
    return c;
  }();
  return catalogue;
}

const EffectInfo &
effectInfo (const std::string &name)
{
  const EffectRegistry &r = EffectRegistry::vocabulary ();
  return r.info (r.index (name));
}

} // namespace texlet
} // namespace pcl
