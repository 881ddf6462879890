#pragma once
// fovlab bench, step 4: its results as Markdown tables, made from the JSON it writes (so the tables
// and the JSON cannot disagree).
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

namespace fovlab::bench {

// GT against IPR, one row per scene and spp (the JSON's "rows"); IPR's columns read "-" where IPR
// was not run.
std::string gt_ipr_table_header();
std::string gt_ipr_table_row(const nlohmann::json& row);

// Median GPU ms per pass of GT and IPR, per scene and spp.
std::string pass_table(const nlohmann::json& rows);

// Where the top level's steps go (bench --step-breakdown): per scene, spp and method (GT, IPR) the
// steps per sample in each category (and their share), the one-surface pixels' share and the share
// of the steps a packet of each such pixel's samples would share. Empty when no row has a breakdown.
std::string step_breakdown_table(const nlohmann::json& rows);

// Every cell (the JSON's "cells": GT, IPR and FIPR), one row each.
std::string cell_table_header();
std::string cell_table_row(const nlohmann::json& cell);

// FIPR at one fovea (scene x spp x refresh: ms, speed-up, SSIM, FLIP), for comparison with Polychronakis et al. 2023's
// Table 1 and section 5.2 at 7.5 degrees; a one-line note when no cell has that fovea.
std::string fovea_table(const nlohmann::json& cells, double fovea_deg);

// The sampling models' cells (Ye et al. 2022): GPU ms, measured speed-up over GT, the speed-up the model is
// set for and the one its shaded samples allow, the share of pixels shaded, PSNR, SSIM, FLIP, FPSNR.
std::string sampling_table(const nlohmann::json& cells);
// The sampling models per scene and spp, over every scene time the cells have (bench --times: seed
// 002's Figure 12 turns its patterns 0-180 degrees): mean FPSNR, PSNR and SSIM, median speed-up,
// ranked by mean FPSNR.
std::string sampling_ranking_table(const nlohmann::json& cells);

// Ye et al. 2022's Figure 6: RMFR's cells over a grid of focal shares (bench --fx A,B,... --fy C,D,...),
// per scene, scene time and spp: the best (f_x, f_y) by FPSNR, PSNR and SSIM (a Markdown table),
// and a heat map (SVG) of each metric over the grid, the best cell outlined. Empty for one pair.
struct FocalSweep {
  std::string table;
  std::vector<std::pair<std::string, std::string>> heat_maps;  // file name, SVG
};
FocalSweep rmfr_focal_sweep(const nlohmann::json& cells, const std::vector<double>& focal_shares_x,
                            const std::vector<double>& focal_shares_y);

// The cells on each scene's Pareto front, for FLIP and for 1 - SSIM.
std::string pareto_table(const nlohmann::json& cells);

}  // namespace fovlab::bench
