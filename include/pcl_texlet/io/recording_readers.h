/*
 * pcl_texlet io: every recording reader and openRecording (). Each has a header of its own; this
 * one is kept for the code that includes them all at once.
 */
#pragma once

#include <pcl_texlet/io/grabber_intrinsics.h>
#include <pcl_texlet/io/grabber_tiff_reader.h>
#include <pcl_texlet/io/oni_reader.h>
#include <pcl_texlet/io/open_recording.h>
#include <pcl_texlet/io/pcd_folder_reader.h>
#include <pcl_texlet/io/recording.h>
#include <pcl_texlet/io/tiff_image.h>
