#include "sweep.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace shore::bench {
namespace {
std::vector<Sweep>& registry() {
  static std::vector<Sweep> list;
  return list;
}
}  // namespace

void Table::add(std::vector<Cell> row) {
  if (row.size() != columns.size())
    throw std::invalid_argument("table " + name + ": row of " + std::to_string(row.size()) + " cells, " +
                                std::to_string(columns.size()) + " columns");
  rows.push_back(std::move(row));
}

std::size_t Table::column(const std::string& c) const {
  const auto it = std::find(columns.begin(), columns.end(), c);
  if (it == columns.end()) throw std::invalid_argument("table " + name + " has no column " + c);
  return static_cast<std::size_t>(it - columns.begin());
}

Table& SweepResult::table(const std::string& name, std::vector<std::string> columns) {
  for (const Table& t : tables_)
    if (t.name == name) throw std::invalid_argument("table " + name + " defined twice");
  tables_.push_back(Table{name, std::move(columns), {}});
  return tables_.back();
}

void SweepResult::figure(const std::string& key, double value, const std::string& unit) {
  const std::size_t dot = key.rfind('.');
  std::string path = "/" + key;
  std::replace(path.begin(), path.end(), '.', '/');
  figures_[nlohmann::json::json_pointer(path)] = value;
  const std::string leaf = dot == std::string::npos ? key : key.substr(dot + 1);
  const std::string parent = dot == std::string::npos ? "" : path.substr(0, path.size() - leaf.size() - 1);
  figures_[nlohmann::json::json_pointer(parent + "/" + leaf + "_unit")] = unit;
  figure_list_.emplace_back(key, unit);
}

void SweepResult::plot(PlotSpec spec) { plots_.push_back(std::move(spec)); }

void SweepResult::note(std::string text) { notes_.push_back(std::move(text)); }

bool Target::pass() const {
  if (!std::isfinite(value)) return false;
  if (op == "<") return value < threshold;
  if (op == "<=") return value <= threshold;
  if (op == ">") return value > threshold;
  return value >= threshold;
}

void SweepResult::target(Target t) {
  if (t.op != "<" && t.op != "<=" && t.op != ">" && t.op != ">=")
    throw std::invalid_argument("target " + t.key + ": op must be <, <=, > or >=, got " + t.op);
  targets_.push_back(std::move(t));
}

const std::vector<Sweep>& sweeps() { return registry(); }

SweepRegistrar::SweepRegistrar(Sweep sweep) {
  auto& list = registry();
  for (const Sweep& s : list)
    if (s.name == sweep.name) throw std::logic_error("sweep " + sweep.name + " registered twice");
  list.push_back(std::move(sweep));
  std::sort(list.begin(), list.end(), [](const Sweep& a, const Sweep& b) { return a.name < b.name; });
}

}  // namespace shore::bench
