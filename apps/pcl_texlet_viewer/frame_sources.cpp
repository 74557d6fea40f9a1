#include "frame_sources.h"

#include <pcl_texlet/camera/depth_image.h>
#include <pcl_texlet/io/guarded_openni2_grabber.h>
#include <pcl_texlet/camera/pinhole_model.h>
#include <pcl_texlet/io/open_recording.h>

#include <pcl/common/io.h> // pcl::copyPointCloud
#include <pcl/exceptions.h>
#include <pcl/io/openni2_grabber.h>
#include <pcl/io/pcd_io.h>

#include <algorithm>
#include <filesystem>
#include <mutex>

namespace fs = std::filesystem;

namespace pcl_texlet_viewer
{

namespace
{

/** Reads a PCD file as texlets (when it has texlet fields) or as an organised cloud. */
Frame
loadPcd (const std::string &file)
{
  pcl::PCLPointCloud2 header;
  Eigen::Vector4f origin;
  Eigen::Quaternionf orientation;
  int version, type;
  unsigned int offset;
  if (!fs::is_regular_file (file))
    throw pcl::IOException ("input '" + file + "' does not exist");
  if (pcl::PCDReader ().readHeader (file, header, origin, orientation, version, type, offset) != 0)
    throw pcl::IOException ("cannot read '" + file + "': not a PCD file or a corrupt header");
  const auto has = [&] (const std::string &name) {
    return std::any_of (header.fields.begin (), header.fields.end (), [&] (const auto &f) { return f.name == name; });
  };
  Frame frame;
  frame.name = fs::path (file).filename ().string ();
  if (has ("cov_p_xx") && has ("normal_x"))
  {
    auto texlets = std::make_shared<Texlets> ();
    if (pcl::io::loadPCDFile (file, *texlets) != 0)
      throw pcl::IOException ("cannot read texlets from '" + file + "': corrupt or truncated");
    frame.texlets = texlets;
    return frame;
  }
  if (!has ("x") || !has ("y") || !has ("z"))
    throw pcl::IOException ("'" + file + "' has no x, y, z fields");
  if (header.height <= 1)
    throw pcl::IOException ("'" + file + "' is not an organised cloud (height " + std::to_string (header.height) + ")");
  auto cloud = std::make_shared<Cloud> ();
  if (pcl::io::loadPCDFile (file, *cloud) != 0 || cloud->size () != std::size_t (header.width) * header.height)
    throw pcl::IOException ("cannot read '" + file + "': corrupt or truncated");
  if (!has ("rgb") && !has ("rgba"))
    for (auto &p : *cloud)
      p.r = p.g = p.b = 200; // a grey scene rather than a black one
  frame.cloud = cloud;
  return frame;
}

/** Files, read in name order and looped. */
class PcdFilesSource : public FrameSource
{
public:
  explicit PcdFilesSource (std::vector<std::string> files, std::string what) : files_ (std::move (files)), what_ (std::move (what)) {}

  bool
  next (Frame &frame) override
  {
    if (files_.size () == 1 && loaded_)
      return false; // a single file is one frame
    frame = loadPcd (files_[next_]);
    next_ = (next_ + 1) % files_.size ();
    loaded_ = true;
    return true;
  }

  std::size_t
  size () const override { return files_.size (); }

  std::string
  describe () const override { return what_; }

private:
  std::vector<std::string> files_;
  std::string what_;
  std::size_t next_ = 0;
  bool loaded_ = false;
};

/** A depth recording (a recording folder or PCL grabber TIFFs), back-projected through its
  * intrinsics, looped. */
class RecordingSource : public FrameSource
{
public:
  explicit RecordingSource (const std::string &folder)
    : folder_ (folder), reader_ (pcl::texlet::openRecording (folder))
  {
    camera_ = std::make_shared<pcl::texlet::PinholeModel> (pcl::texlet::PinholeModel::fromCameraInfo (reader_->cameraInfo ()));
  }

  bool
  next (Frame &frame) override
  {
    pcl::texlet::DepthFrame depth;
    if (!reader_->next (depth))
    {
      reader_ = pcl::texlet::openRecording (folder_);
      if (!reader_->next (depth))
        return false;
    }
    auto cloud = std::make_shared<Cloud> ();
    pcl::texlet::depthToCloud (depth, *camera_, *cloud);
    if (depth.rgb.empty ())
      for (auto &p : *cloud)
        p.r = p.g = p.b = 200;
    frame.cloud = cloud;
    frame.texlets.reset ();
    frame.camera = camera_;
    frame.name = depth.name;
    return true;
  }

  std::size_t
  size () const override { return reader_->size (); }

  std::string
  describe () const override { return "recording " + folder_; }

private:
  std::string folder_;
  pcl::texlet::RecordingReader::Ptr reader_;
  pcl::texlet::CameraModel::ConstPtr camera_;
};

/** An OpenNI2 device or .oni file through PCL's grabber, guarded so that it stops safely while
  * frames flow: the newest cloud wins.
  */
class GrabberSource : public FrameSource
{
public:
  explicit GrabberSource (const std::string &device) : device_ (device.empty () ? "first OpenNI2 sensor" : device)
  {
    grabber_ = std::make_unique<pcl::texlet::GuardedOpenNI2Grabber> (device);
    using DepthOnlyCloud = pcl::PointCloud<pcl::PointXYZ>;
    if (grabber_->providesCallback<void (const Cloud::ConstPtr &)> ())
    {
      std::function<void (const Cloud::ConstPtr &)> f = [this] (const Cloud::ConstPtr &cloud) {
        std::lock_guard<std::mutex> lock (mutex_);
        latest_ = cloud;
      };
      grabber_->registerCallback (f);
    }
    else // a depth-only device (no colour sensor): the grabber offers XYZ clouds only
    {
      std::function<void (const DepthOnlyCloud::ConstPtr &)> f = [this] (const DepthOnlyCloud::ConstPtr &xyz) {
        auto cloud = std::make_shared<Cloud> ();
        pcl::copyPointCloud (*xyz, *cloud);
        for (auto &p : *cloud)
          p.r = p.g = p.b = p.a = 255; // a depth sensor sees no colour: white points
        std::lock_guard<std::mutex> lock (mutex_);
        latest_ = cloud;
      };
      grabber_->registerCallback (f);
    }
    grabber_->start ();
  }

  ~GrabberSource () override
  {
    // Waits for the grabber's callbacks in flight (they use mutex_ and latest_) before the
    // members go; PCL's own stop () would not.
    grabber_->stop ();
  }

  bool
  next (Frame &frame) override
  {
    std::lock_guard<std::mutex> lock (mutex_);
    if (!latest_)
      return false;
    frame.cloud = latest_;
    frame.texlets.reset ();
    frame.camera.reset ();
    frame.name = device_;
    latest_.reset ();
    return true;
  }

  std::size_t
  size () const override { return 0; }

  std::string
  describe () const override { return device_; }

private:
  std::string device_;
  std::unique_ptr<pcl::texlet::GuardedOpenNI2Grabber> grabber_;
  std::mutex mutex_;
  Cloud::ConstPtr latest_;
};

} // namespace

FrameSource::Ptr
openSource (const std::string &input)
{
  if (input == "sensor")
  {
    auto s = openFirstSensor ();
    if (!s)
      throw pcl::IOException ("no OpenNI2 sensor is connected");
    return s;
  }
  if (fs::is_directory (input))
  {
    const auto kind = pcl::texlet::recordingKind (input); // throws, naming the folder, for none
    if (kind == pcl::texlet::RecordingKind::recording_folder || kind == pcl::texlet::RecordingKind::grabber_tiff_folder ||
        kind == pcl::texlet::RecordingKind::kinect_disparity_folder)
      return std::make_unique<RecordingSource> (input);
    std::vector<std::string> files;
    for (const auto &e : fs::directory_iterator (input))
      if (e.is_regular_file () && e.path ().extension () == ".pcd")
        files.push_back (e.path ().string ());
    if (files.empty ())
      throw pcl::IOException ("folder '" + input + "' has neither camera.yaml + depth/ (a recording) nor *.pcd files");
    std::sort (files.begin (), files.end ());
    return std::make_unique<PcdFilesSource> (files, "folder " + input);
  }
  if (fs::path (input).extension () == ".oni")
  {
    if (!fs::is_regular_file (input))
      throw pcl::IOException ("input '" + input + "' does not exist");
    try
    {
      return std::make_unique<GrabberSource> (input);
    }
    catch (const pcl::PCLException &e)
    {
      throw pcl::IOException ("cannot play '" + input + "': " + e.detailedMessage ());
    }
  }
  loadPcd (input); // checks the file before the viewer opens
  return std::make_unique<PcdFilesSource> (std::vector<std::string>{input}, input);
}

FrameSource::Ptr
openFirstSensor ()
{
  try
  {
    return std::make_unique<GrabberSource> ("");
  }
  catch (const pcl::PCLException &)
  {
    return nullptr; // no device: the caller falls back to files
  }
}

} // namespace pcl_texlet_viewer
