#pragma once
/// \file
/// The rove subcommands. Each registers itself on the CLI11 application.

#include <CLI/CLI.hpp>

namespace rove::cli {

/// `rove demo`: the job the README's quick start runs on bundled data.
void add_demo_command(CLI::App& app);
/// `rove config check FILE...`: load MRPT-style INI files and report.
void add_config_command(CLI::App& app);
/// `rove rawlog info|convert|export-scans|export-odometry|cut|decimate`:
/// inspect, convert and export rove/MRPT rawlogs and CARMEN logs.
void add_rawlog_command(CLI::App& app);
/// `rove icp-slam [CONFIG] [RAWLOG] [-o DIR] [--json]`: build a map with ICP-SLAM.
void add_icp_slam_command(CLI::App& app);
/// `rove lidar-slam [CONFIG] LOG [-o DIR] [--json]`: 2D lidar SLAM with loop
/// closure.
void add_lidar_slam_command(CLI::App& app);
/// `rove rgbd-slam INPUT [--config rgbd.ini] [-o DIR] [--json]`: RGB-D SLAM over
/// a TUM, ICL-NUIM or numbered-frames folder (only when rove::vision is built).
void add_rgbd_slam_command(CLI::App& app);
/// `rove pf-localization [CONFIG] [RAWLOG] [-o DIR] [--seed N] [--json]`:
/// Monte-Carlo localization in a known map from an MRPT pf-localization config.
void add_pf_localization_command(CLI::App& app);
/// `rove kf-slam`: EKF landmark SLAM from an MRPT kf-slam config.
void add_kf_slam_command(CLI::App& app);
/// `rove rbpf-slam CONFIG [RAWLOG] [-o DIR] [--seed N] [--json]`: Rao-Blackwellized
/// particle-filter grid mapping from an MRPT rbpf-slam config.
void add_rbpf_slam_command(CLI::App& app);
/// `rove map build CONFIG INPUT -o DIR [--section S] [--json]`: build the
/// maps an MRPT config declares from a rawlog or simplemap; `rove map
/// convert IN OUT`: occupancy grids between ROS map.yaml, .gridmap, .rovegrid.
void add_map_command(CLI::App& app);
/// `rove graph-slam -i IN [-o OUT] [--solver ...] [--init ...] [--info] [--plot PNG] [--json]`:
/// optimize or inspect a 2D/3D pose graph.
void add_graph_slam_command(CLI::App& app);
/// `rove align SOURCE TARGET [--method icp|point-to-plane|gicp|ndt] [--init ...] [--voxel L]`:
/// register two point clouds and print T_target_source.
void add_align_command(CLI::App& app);
/// `rove eval ate|rpe|relations`: trajectory evaluation against ground
/// truth or relations.
void add_eval_command(CLI::App& app);
/// `rove octomap build INPUT... -o MAP.bt [--res R] [--poses TRAJ] [--json]`:
/// a 3D occupancy octree (OctoMap's .bt/.ot) from point clouds.
void add_octomap_command(CLI::App& app);
/// `rove nav plan MAP --start x,y --goal x,y -o PATH.tum`: grid path planning
/// for a disc robot.
void add_nav_command(CLI::App& app);
/// `rove view FILE... [--port P] [--export S.glb] [--html P.html] [--screenshot P.png]`:
/// one 3D scene from rove's files and output folders, in a web browser.
void add_view_command(CLI::App& app);
/// `rove batch COMMAND [--inputs ...] [--param SECTION.key=V1,V2] [-o DIR] ...`:
/// listed in the help; the arguments after `batch` go to run_batch_command().
void add_batch_command(CLI::App& app);
/// Replaces the process with `python3 -m rove.batch ARGS...` (the Dask
/// scale-out, python/rove/batch.py); returns only if that cannot start.
int run_batch_command(int argc, char** argv);

}  // namespace rove::cli
