#pragma once
// <out>/report.md: every scene found under <out> (a folder with a metrics.json), with its
// description, its pictures, its metrics and a one-line explanation of each.

#include <filesystem>

namespace shore::scenes {

/// Writes out_root/report.md from the metrics.json files under out_root; returns its path.
std::filesystem::path write_report(const std::filesystem::path& out_root);

}  // namespace shore::scenes
