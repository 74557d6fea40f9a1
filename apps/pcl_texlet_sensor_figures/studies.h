/*
 * pcl_texlet_sensor_figures: the studies, one a file named after its figure (measureRadial in
 * radial.cpp). Each simulates its scenes with the base noise alone and with its effect, writes its
 * data files through Figures::write and its key numbers through Figures::note. This header holds
 * what they all use.
 */
#pragma once

#include "figures.h"
#include "measurements.h"

#include <pcl_texlet/kernels/structured_light.h>
#include <pcl_texlet/simulation/effects.h>
#include <pcl_texlet/simulation/scene.h>
#include <pcl_texlet/simulation/scene_setup.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

namespace pcl_texlet_sensor_figures
{

// The studies are written in the project's names.
using namespace pcl::texlet;
using namespace pcl::texlet::sim;

/** \brief The paper's polynomial alone: SD vs radius at three depths, and the SD map at 1.5 m. */
void
measureBaseNoise (Figures &figures);

/** \brief The own projector's shadow beside a step: width vs background depth, and a row profile. */
void
measureProjectorShadows (Figures &figures);

/** \brief SD vs depth on a frontal wall, central window: base alone and base + axial_quadratic. */
void
measureAxialQuadratic (Figures &figures);

/** \brief SD vs radius on a frontal wall at 1.5 m: base alone and base + radial. */
void
measureRadial (Figures &figures);

/** \brief Depth histogram on a frontal wall and the mean-error staircase on a tilted one. */
void
measureDisparityQuantization (Figures &figures);

/** \brief SD and readings vs the wall's tilt, central window: base alone and base + incidence_angle. */
void
measureIncidenceAngle (Figures &figures);

/** \brief Column means of one frame's residual, and the residual map: base alone and base + stripes. */
void
measureVerticalStripes (Figures &figures);

/** \brief The static bias map at 1.5 m and its central-row profile at three depths. */
void
measureDepthDistortion (Figures &figures);

/** \brief Holes and SD vs the number of active projectors: a wall at 1.5 m seen by 1-3 sensors. */
void
measureInterference (Figures &figures);

/** \brief Frame means of the residual vs frame index: base alone and base + temporal_drift. */
void
measureTemporalDrift (Figures &figures);

/** \brief Which side of a depth step each pixel reports, by column: base alone and base + lateral_noise. */
void
measureLateralNoise (Figures &figures);

/** \brief Geometry back-projected with the labelled intrinsics: lateral error and fitted wall tilt. */
void
measureIntrinsics (Figures &figures);

} // namespace pcl_texlet_sensor_figures
