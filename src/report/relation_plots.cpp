#include <pcl_texlet/report/relation_plots.h>

#include <pcl_texlet/common/atomic_file.h>
#include <pcl_texlet/report/gnuplot.h>

#include <pcl/exceptions.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <system_error>

#include <unistd.h>

namespace fs = std::filesystem;

namespace pcl
{
namespace texlet
{

namespace
{

/** gnuplot's string syntax (double quotes, escaped). */
std::string
gpString (const std::string &s)
{
  std::string out = "\"";
  for (char c : s)
  {
    if (c == '"' || c == '\\')
      out += '\\';
    out += c;
  }
  return out + "\"";
}

/** A scratch folder removed on destruction. */
class ScratchFolder
{
public:
  ScratchFolder ()
  {
    static int counter = 0;
    path_ = fs::temp_directory_path () /
            ("pcl_texlet_plot." + std::to_string (::getpid ()) + "." + std::to_string (counter++));
    fs::create_directories (path_);
  }
  ~ScratchFolder ()
  {
    std::error_code ec;
    fs::remove_all (path_, ec);
  }
  std::string
  file (const std::string &name) const { return (path_ / name).string (); }

private:
  fs::path path_;
};

/** Runs \a script, which must `set output` to \a png's temporary path, and renames the PNG it
  * drew onto \a png's path.
  */
void
drawPng (const ScratchFolder &scratch, const std::string &script, AtomicFile &png)
{
  const std::string script_file = scratch.file ("plot.gp");
  {
    std::ofstream out (script_file);
    out << script;
    if (!out)
      throw pcl::IOException ("cannot write a gnuplot script to '" + script_file + "'");
  }
  runGnuplot (script_file, scratch.file ("gnuplot.log"));
  std::error_code ec;
  if (!fs::is_regular_file (png.temporaryPath (), ec) || fs::file_size (png.temporaryPath (), ec) == 0)
    throw pcl::IOException ("gnuplot drew no image for '" + png.path () + "' (script '" + script_file + "')");
  png.commit ();
}

} // namespace

void
writeRelationHistogramPng (const RelationStatistics &stats, const std::string &png, const std::string &title)
{
  const auto &axes = stats.axes;
  if (stats.histogram.size () != static_cast<std::size_t> (axes.distance_bins) * axes.angle_bins)
    throw pcl::BadArgumentException ("writeRelationHistogramPng: the histogram does not match its axes");
  ScratchFolder scratch;
  const std::string data = scratch.file ("histogram.dat");
  {
    std::ofstream out (data);
    out << std::setprecision (6);
    for (int a = 0; a < axes.angle_bins; ++a)
    {
      for (int d = 0; d < axes.distance_bins; ++d)
      {
        const std::uint64_t c = stats.count (d, a);
        // Raw counts: every bin is written so that the grid stays regular for `with image`
        // (a missing value would shift the rest of its row); empty bins become NaN in the plot.
        out << 1000.0 * stats.distanceBinCentre (d) << ' ' << stats.angleBinCentre (a) << ' ' << c << '\n';
      }
      out << '\n';
    }
    if (!out)
      throw pcl::IOException ("cannot write the histogram data to '" + data + "'");
  }
  AtomicFile file (png);
  std::ostringstream gp;
  gp << "set terminal pngcairo size 900,660 enhanced font 'Sans,11'\n"
     << "set output " << gpString (file.temporaryPath ()) << "\n"
     << "set title " << gpString (title) << "\n"
     << "set xlabel 'normal distance n_{ij} (mm)'\nset ylabel 'angle between normals {/Symbol q} (degrees)'\n"
     << "set cblabel 'log_{10} (relations per bin)'\n"
     << "set bmargin 5\n"
     << "set xrange [0:" << 1000.0 * axes.distance_max << "]\nset yrange [0:180]\nset ytics 30\n"
     << "set palette defined (0 '#000080', 1 '#0060ff', 2 '#00d0d0', 3 '#80ff40', 4 '#ffd000', 5 '#ff4000', 6 '#800000')\n"
     << "set cbrange [0:*]\nset key off\n";
  int obj = 1;
  for (const auto &r : stats.relations)
  {
    const double x0 = std::max (0.0, 1000.0 * (r.distance_min_m - stats.distance_tol_m));
    const double x1 = 1000.0 * (r.distance_max_m + stats.distance_tol_m);
    const double y0 = std::max (0.0, r.angle_deg - stats.angle_tol_deg);
    const double y1 = std::min (180.0, r.angle_deg + stats.angle_tol_deg);
    gp << "set object " << obj++ << " rect from " << x0 << "," << y0 << " to " << x1 << "," << y1
       << " front fillstyle empty border rgb '#00a000' lw 1.5\n";
  }
  gp << "set label 1 " << gpString ("inliers " + [&] {
    std::ostringstream s;
    s << std::fixed << std::setprecision (1) << stats.inlierPercent () << " % of " << stats.relation_count
      << " relations (" << stats.texlets << " texlets)";
    return s.str ();
  }()) << " at screen 0.5, screen 0.035 center front tc rgb '#000000'\n";
  gp << "plot " << gpString (data) << " using 1:2:($3 > 0 ? log10($3) : NaN) with image\n";
  drawPng (scratch, gp.str (), file);
}

void
writeInlierCurvesPng (const std::vector<InlierCurve> &curves, const std::string &png, const std::string &title,
                      const std::string &y_label)
{
  if (curves.empty ())
    throw pcl::BadArgumentException ("writeInlierCurvesPng: no curves");
  ScratchFolder scratch;
  std::ostringstream plot;
  for (std::size_t c = 0; c < curves.size (); ++c)
  {
    const auto &curve = curves[c];
    if (curve.radius_px.size () != curve.percent.size ())
      throw pcl::BadArgumentException ("writeInlierCurvesPng: curve '" + curve.label + "' has unequal x and y");
    const std::string data = scratch.file ("curve" + std::to_string (c) + ".dat");
    std::ofstream out (data);
    for (std::size_t i = 0; i < curve.radius_px.size (); ++i)
      out << curve.radius_px[i] << ' ' << curve.percent[i] << '\n';
    if (!out)
      throw pcl::IOException ("cannot write '" + data + "'");
    plot << (c ? ", " : "plot ") << gpString (data) << " using 1:2 with linespoints lw 2 pt 7 title "
         << gpString (curve.label);
  }
  AtomicFile file (png);
  std::ostringstream gp;
  gp << "set terminal pngcairo size 800,560 enhanced font 'Sans,11'\n"
     << "set output " << gpString (file.temporaryPath ()) << "\n"
     << "set title " << gpString (title) << "\n"
     << "set xlabel 'neighbourhood radius (pixels)'\nset ylabel " << gpString (y_label) << "\n"
     << "set grid\nset key bottom right box\nset yrange [0:*]\n"
     << plot.str () << "\n";
  drawPng (scratch, gp.str (), file);
}

} // namespace texlet
} // namespace pcl
