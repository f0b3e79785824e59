#include "common/graph_file/graph_file.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "common/files/durable_file.h"
#include "common/files/shell_path.h"
#include "common/files/small_file.h"
#include "common/graph_file/json.h"

namespace srics::graph_file {
namespace {

constexpr const char* kFormat = "srics-interaction-graph";
// 2: "readout" and "edge_scores" (the threshold applies to them); 1: mean weights only
constexpr int kFormatVersion = 2;

uint64_t Fnv1a(const std::string& text) {
  uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}

std::string Hex(uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

// shortest text that reads back as the same double
std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

std::string EntityName(int e) { return e == 0 ? "arm" : "puck " + std::to_string(e); }

void Fail(const std::string& what) { throw std::runtime_error("interaction graph file: " + what); }

}  // namespace

LearnedGraph AggregateGraph(int n, const std::vector<double>& w, double threshold, int action_entity) {
  if (n < 2 || n > rl::kMaxGraphEntities) throw std::invalid_argument("AggregateGraph: entity count out of range");
  if (w.size() != static_cast<size_t>(n) * n) throw std::invalid_argument("AggregateGraph: weight matrix is not N x N");
  if (action_entity < 0 || action_entity >= n)
    throw std::invalid_argument("AggregateGraph: action entity out of range");
  LearnedGraph out;
  out.threshold = threshold;
  out.edge_scores = w;
  out.graph.num_entities = n;
  out.graph.action_entity = action_entity;
  out.graph.adjacency.assign(w.size(), 0);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      const double v = w[static_cast<size_t>(i) * n + j];
      if (!std::isfinite(v)) throw std::invalid_argument("AggregateGraph: weight not finite");
      if (i == j) {
        out.edge_scores[static_cast<size_t>(i) * n + j] = 0;  // no self edges
        continue;
      }
      out.graph.adjacency[static_cast<size_t>(i) * n + j] = v > threshold ? 1 : 0;
    }
  }
  out.structure = rl::ComputeSubgoalStructure(out.graph);
  out.mean_weights = out.edge_scores;
  return out;
}

bool SameStructure(const rl::InteractionGraph& a, const rl::InteractionGraph& b) {
  return a.num_entities == b.num_entities && a.action_entity == b.action_entity && a.adjacency == b.adjacency;
}

std::string GraphToJson(const LearnedGraph& g) {
  const int n = g.num_entities();
  std::ostringstream s;
  s << "{\n";
  s << "  \"format\": \"" << kFormat << "\",\n";
  s << "  \"format_version\": " << kFormatVersion << ",\n";
  s << "  \"version\": " << g.version << ",\n";
  s << "  \"num_entities\": " << n << ",\n";
  s << "  \"action_entity\": " << g.graph.action_entity << ",\n";
  s << "  \"readout\": \"" << g.readout << "\",\n";
  s << "  \"threshold\": " << Num(g.threshold) << ",\n";
  s << "  \"held_out_loss\": " << Num(g.held_out_loss) << ",\n";
  s << "  \"updates\": " << g.updates << ",\n";
  s << "  \"episodes\": " << g.episodes << ",\n";
  s << "  \"edges\": \"" << rl::DescribeGraph(g.graph) << "\",\n";
  auto list = [&](const auto& values) {
    std::string text = "[";
    for (size_t i = 0; i < values.size(); ++i) {
      if (i) text += ", ";
      if constexpr (std::is_floating_point_v<std::decay_t<decltype(values[0])>>)
        text += Num(values[i]);
      else
        text += std::to_string(values[i]);
    }
    return text + "]";
  };
  s << "  \"entity_kinds\": " << list(g.entity_kinds) << ",\n";
  s << "  \"action_correlation\": " << list(g.action_correlation) << ",\n";
  // matrices row by row (row = from), readable in a text editor
  auto matrix = [&](const char* name, const std::vector<double>& m) {
    s << "  \"" << name << "\": [\n";
    for (int i = 0; i < n; ++i) {
      std::vector<double> row(m.begin() + static_cast<size_t>(i) * n, m.begin() + static_cast<size_t>(i + 1) * n);
      s << "    " << list(row) << (i + 1 < n ? ",\n" : "\n");
    }
    s << "  ],\n";
  };
  matrix("edge_scores", g.edge_scores);
  matrix("mean_weights", g.mean_weights);
  s << "  \"adjacency\": [\n";
  for (int i = 0; i < n; ++i) {
    std::vector<int> row(n);
    for (int j = 0; j < n; ++j) row[j] = g.graph.edge(i, j) ? 1 : 0;
    s << "    " << list(row) << (i + 1 < n ? ",\n" : "\n");
  }
  s << "  ],\n";
  s << "  \"ancestor_masks\": " << list(g.structure.ancestor_mask) << ",\n";
  s << "  \"depths\": " << list(g.structure.depth);
  // the checksum covers every byte before it
  const std::string body = s.str();
  return body + ",\n  \"checksum\": \"" + Hex(Fnv1a(body)) + "\"\n}\n";
}

namespace {

// The JSON document of a graph file whose checksum matches (format and version checked).
JsonValue CheckedRoot(const std::string& text) {
  // checksum first: every byte before `,\n  "checksum"` is covered
  const std::string marker = ",\n  \"checksum\": \"";
  const size_t at = text.rfind(marker);
  if (at == std::string::npos) Fail("no checksum (truncated?)");
  const std::string stored = text.substr(at + marker.size(), 16);
  if (stored != Hex(Fnv1a(text.substr(0, at)))) Fail("checksum mismatch (corrupted)");
  JsonValue root;
  try {
    root = ParseJson(text);
  } catch (const std::exception& e) {
    Fail(e.what());
  }
  if (!root.is_object()) Fail("top level is not an object");
  if (root.Get("format").AsString() != kFormat) Fail("not an interaction graph (format)");
  const int64_t version = root.Get("format_version").AsInt();
  if (version != 1 && version != kFormatVersion) Fail("unsupported format version " + std::to_string(version));
  return root;
}

}  // namespace

LearnedGraph GraphFromJson(const std::string& text) {
  const JsonValue root = CheckedRoot(text);
  LearnedGraph g;
  const int64_t version = root.Get("version").AsInt();
  if (version < 0) Fail("negative version");
  g.version = static_cast<uint64_t>(version);
  const int64_t n = root.Get("num_entities").AsInt();
  if (n < 2 || n > rl::kMaxGraphEntities) Fail("num_entities " + std::to_string(n) + " out of range");
  const int64_t action = root.Get("action_entity").AsInt();
  if (action < 0 || action >= n) Fail("action_entity out of range");
  g.threshold = root.Get("threshold").AsDouble();
  if (!(g.threshold >= 0 && g.threshold <= 1)) Fail("threshold outside [0, 1]");
  g.held_out_loss = root.Get("held_out_loss").AsDouble();
  if (!std::isfinite(g.held_out_loss) || g.held_out_loss < 0) Fail("bad held_out_loss");
  g.updates = root.Get("updates").AsInt();
  g.episodes = static_cast<int>(root.Get("episodes").AsInt());
  if (g.updates < 0 || g.episodes < 0) Fail("negative updates or episodes");
  for (const JsonValue& v : root.Get("entity_kinds").AsArray()) {
    const int64_t kind = v.AsInt();
    if (kind < 0 || kind > 65535) Fail("entity kind out of range");
    g.entity_kinds.push_back(static_cast<int>(kind));
  }
  if (static_cast<int64_t>(g.entity_kinds.size()) != n) Fail("entity_kinds size differs from num_entities");
  for (const JsonValue& v : root.Get("action_correlation").AsArray()) g.action_correlation.push_back(v.AsDouble());
  if (static_cast<int64_t>(g.action_correlation.size()) != n) Fail("action_correlation size");
  // the matrices must be N rows of N, values in [0, 1], zero diagonal
  auto read_matrix = [&](const char* name) {
    const auto& rows = root.Get(name).AsArray();
    if (static_cast<int64_t>(rows.size()) != n) Fail(std::string(name) + " must have num_entities rows");
    std::vector<double> m;
    for (int64_t i = 0; i < n; ++i) {
      const auto& r = rows[i].AsArray();
      if (static_cast<int64_t>(r.size()) != n)
        Fail(std::string(name) + " row " + std::to_string(i) + " does not have num_entities columns");
      for (int64_t j = 0; j < n; ++j) {
        const double w = r[j].AsDouble();
        if (!(w >= 0 && w <= 1)) Fail(std::string(name) + " value outside [0, 1]");
        if (i == j && w != 0) Fail(std::string(name) + ": non-zero self value");
        m.push_back(w);
      }
    }
    return m;
  };
  const bool v1 = root.Get("format_version").AsInt() == 1;
  g.readout = v1 ? "mean_weight" : root.Get("readout").AsString();
  if (g.readout != "cut" && g.readout != "mean_weight" && g.readout != "mean_weight_apart")
    Fail("unknown readout '" + g.readout + "'");
  const std::vector<double> mean_weights = read_matrix("mean_weights");
  const std::vector<double> weights = v1 ? mean_weights : read_matrix("edge_scores");
  const auto& adj = root.Get("adjacency").AsArray();
  if (static_cast<int64_t>(adj.size()) != n) Fail("adjacency must have num_entities rows");
  std::vector<uint8_t> adjacency;
  for (int64_t i = 0; i < n; ++i) {
    const auto& ar = adj[i].AsArray();
    if (static_cast<int64_t>(ar.size()) != n)
      Fail("adjacency row " + std::to_string(i) + " does not have num_entities columns");
    for (int64_t j = 0; j < n; ++j) {
      const int64_t a = ar[j].AsInt();
      if (a != 0 && a != 1) Fail("adjacency entries must be 0 or 1");
      adjacency.push_back(static_cast<uint8_t>(a));
    }
  }
  // everything derived must follow from the weights, threshold and action entity
  LearnedGraph derived = AggregateGraph(static_cast<int>(n), weights, g.threshold, static_cast<int>(action));
  if (derived.graph.adjacency != adjacency) Fail("adjacency does not match the edge scores and threshold");
  std::vector<int64_t> depths, masks;
  for (const JsonValue& v : root.Get("depths").AsArray()) depths.push_back(v.AsInt());
  for (const JsonValue& v : root.Get("ancestor_masks").AsArray()) masks.push_back(v.AsInt());
  for (size_t i = 0; i < derived.structure.depth.size(); ++i) {
    if (depths.size() != derived.structure.depth.size() || depths[i] != derived.structure.depth[i])
      Fail("depths do not follow from the adjacency");
    if (masks.size() != derived.structure.ancestor_mask.size() ||
        masks[i] != static_cast<int64_t>(derived.structure.ancestor_mask[i]))
      Fail("ancestor masks do not follow from the adjacency");
  }
  g.graph = std::move(derived.graph);
  g.structure = std::move(derived.structure);
  g.edge_scores = std::move(derived.edge_scores);
  g.mean_weights = mean_weights;
  return g;
}

void SaveGraph(const LearnedGraph& graph, const std::string& path) {
  files::WriteFileDurably(path, GraphToJson(graph));  // throws files::FileError (a runtime_error)
}

LearnedGraph LoadGraph(const std::string& path) {
  std::string text;
  try {
    text = files::ReadSmallFile(path);
  } catch (const files::SmallFileError& e) {
    throw std::runtime_error(std::string("interaction graph file: ") + e.what());
  }
  try {
    return GraphFromJson(text);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string(e.what()) + " (" + path + ")");
  }
}

std::string GraphDot(const LearnedGraph& g) {
  const int n = g.num_entities();
  std::ostringstream s;
  s << "digraph interaction {\n  rankdir=LR;\n  node [fontname=\"Helvetica\"];\n";
  s << "  label=\"version " << g.version << ", " << g.updates << " updates, " << g.readout << " read-out, threshold "
    << g.threshold << "\";\n";
  s << "  action [shape=diamond, style=filled, fillcolor=\"#f4d35e\", label=\"action\"];\n";
  for (int e = 0; e < n; ++e) {
    const bool subgoal = g.structure.has_subgoal(e);
    s << "  e" << e << " [shape=" << (e == g.graph.action_entity ? "box" : "ellipse") << ", style=filled, fillcolor=\""
      << (subgoal ? "#9ad1d4" : "#dddddd") << "\", label=\"" << EntityName(e) << "\\ndepth " << g.structure.depth[e]
      << "\"];\n";
  }
  s << "  action -> e" << g.graph.action_entity << " [penwidth=2];\n";
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      if (i == j || !g.graph.edge(i, j)) continue;
      char w[32];
      std::snprintf(w, sizeof w, "%.3f", g.edge_scores[static_cast<size_t>(i) * n + j]);
      s << "  e" << i << " -> e" << j << " [label=\"" << w << "\"];\n";
    }
  s << "}\n";
  return s.str();
}

std::string HeatMapDot(const LearnedGraph& g) {
  const int n = g.num_entities();
  std::ostringstream s;
  s << "digraph weights {\n  node [shape=plaintext, fontname=\"Helvetica\"];\n";
  s << "  m [label=<<table border=\"0\" cellborder=\"1\" cellspacing=\"0\" cellpadding=\"8\">\n";
  s << "  <tr><td colspan=\"" << n + 1 << "\">" << (g.readout == "cut" ? "cut score" : "mean edge weight")
    << " (row acts on column), threshold " << g.threshold << "</td></tr>\n  <tr><td>from \\ to</td>";
  for (int j = 0; j < n; ++j) s << "<td>" << EntityName(j) << "</td>";
  s << "</tr>\n";
  for (int i = 0; i < n; ++i) {
    s << "  <tr><td>" << EntityName(i) << "</td>";
    for (int j = 0; j < n; ++j) {
      const double w = g.edge_scores[static_cast<size_t>(i) * n + j];
      // white (0) to dark red (1)
      const double v = std::clamp(w, 0.0, 1.0);
      const int gb = static_cast<int>(255 * (1 - v));
      char color[8];
      std::snprintf(color, sizeof color, "#ff%02x%02x", gb, gb);
      char text[32];
      std::snprintf(text, sizeof text, i == j ? "-" : "%.3f", w);
      const bool kept = i != j && g.graph.edge(i, j);
      s << "<td bgcolor=\"" << (i == j ? "#eeeeee" : color) << "\">" << (kept ? "<b>" : "") << text
        << (kept ? "</b>" : "") << "</td>";
    }
    s << "</tr>\n";
  }
  s << "  </table>>];\n}\n";
  return s.str();
}

bool RenderDotToPng(const std::string& dot_text, const std::string& png_path, std::string* error) {
  FILE* pipe = ::popen(("dot -Tpng -o " + files::ShellQuote(png_path) + " > /dev/null 2>&1").c_str(), "w");
  if (!pipe) {
    *error = "cannot run graphviz's dot";
    return false;
  }
  const bool written = std::fwrite(dot_text.data(), 1, dot_text.size(), pipe) == dot_text.size();
  const int status = ::pclose(pipe);
  if (!written || status != 0) {
    *error = "graphviz's dot failed (status " + std::to_string(status) + "; is graphviz installed?)";
    return false;
  }
  return true;
}

std::string SaveGraphWithPictures(const LearnedGraph& graph, const std::string& prefix) {
  SaveGraph(graph, prefix + ".json");
  std::string missing;
  for (const auto& [suffix, text] :
       {std::pair<std::string, std::string>{"", GraphDot(graph)}, {"_weights", HeatMapDot(graph)}}) {
    const std::string dot = prefix + suffix + ".dot";
    {
      std::ofstream out(dot, std::ios::trunc);
      out << text;
    }
    std::string error;
    if (!RenderDotToPng(text, prefix + suffix + ".png", &error)) missing += (missing.empty() ? "" : ", ") + dot;
  }
  return missing;
}

rl::GraphUpdate ToGraphUpdate(const LearnedGraph& g) {
  rl::GraphUpdate u;
  u.version = g.version;
  u.graph = g.graph;
  u.structure = g.structure;
  u.mean_weights = g.edge_scores;  // what the threshold applies to (the wire's name is older)
  u.threshold = g.threshold;
  u.held_out_loss = g.held_out_loss;
  u.training_updates = static_cast<uint64_t>(g.updates);
  u.episodes_used = static_cast<uint32_t>(g.episodes);
  return u;
}

}  // namespace srics::graph_file
