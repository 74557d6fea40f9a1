/*
 * pcl_texlet io: the recording folder format whole (the reader interface, the folder reader,
 * camera.yaml, PNG). Each has a header of its own; this one is kept for the code that includes
 * them all at once.
 */
#pragma once

#include <pcl_texlet/io/camera_yaml.h>
#include <pcl_texlet/io/png_image.h>
#include <pcl_texlet/io/recording_folder_reader.h>
#include <pcl_texlet/io/recording_reader.h>
