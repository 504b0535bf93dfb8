#include "rov_tether/spec/yaml_read.hpp"

#include <yaml-cpp/eventhandler.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <utility>
#include <vector>

namespace rov_tether::spec
{

namespace
{

/// Deeper nesting than any scenario has (a `tethers` entry's sections are 4 levels deep) is refused: an alias
/// inside the node its anchor names (`params: &p {a: *p}`) makes yaml-cpp's node graph a cycle, which every walk
/// of it would follow for ever (fuzz_scenario: a stack overflow here).
constexpr int kMaxYamlDepth = 64;
/// More values than this, counting each alias's as often as it is used, are refused: aliases of lists of aliases
/// (`l1: &l1 [*l0, *l0, ...]`, ten levels of ten) make a 700-byte file 1e10 values, which this walk and every
/// reader after it would take hours to go through. A dive's recorded path at 10 Hz for an hour is 180,000.
constexpr long kMaxYamlValues = 10000000;

/// Where each document's first node starts. yaml-cpp 0.7 (Debian 12's) reads a ',' where no value can start (at
/// the start of a document, or after a flow sequence at block level: `[1, 2], 3`) as an endless run of empty
/// documents at that same place (yaml-cpp issue #1040, fixed upstream by pull request #1319): YAML::LoadAll
/// filled the memory (fuzz_scenario: a 600-byte scenario took 20 GB) and YAML::Load read it as an empty file.
class DocumentStarts : public YAML::EventHandler
{
 public:
  /// Where the last document's first node starts.
  const YAML::Mark& mark() const { return start_; }

  void OnDocumentStart(const YAML::Mark& /*mark*/) override { first_ = true; }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t /*anchor*/) override { note(mark); }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t /*anchor*/) override { note(mark); }
  void OnScalar(const YAML::Mark& mark, const std::string& /*tag*/, YAML::anchor_t /*anchor*/,
                const std::string& /*value*/) override
  {
    note(mark);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string& /*tag*/, YAML::anchor_t /*anchor*/,
                       YAML::EmitterStyle::value /*style*/) override
  {
    note(mark);
  }
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark& mark, const std::string& /*tag*/, YAML::anchor_t /*anchor*/,
                  YAML::EmitterStyle::value /*style*/) override
  {
    note(mark);
  }
  void OnMapEnd() override {}

 private:
  void note(const YAML::Mark& mark)
  {
    if (first_)
    {
      start_ = mark;
      first_ = false;
    }
  }
  bool first_ = false;
  YAML::Mark start_;
};

/// Throws YAML::ParserException where the parser stops making progress (two documents starting at the same
/// place: DocumentStarts), before YAML::LoadAll would loop there.
void refuseEndlessDocuments(const std::string& text)
{
  std::istringstream in(text);
  YAML::Parser parser(in);
  DocumentStarts starts;
  int previous = -1;  // no document yet
  while (parser.HandleNextDocument(starts))
  {
    if (starts.mark().pos == previous)
    {
      throw YAML::ParserException(starts.mark(),
                                  "a ',' (or another token) where no value can start: outside [ ] or { }, a ',' "
                                  "separates nothing");
    }
    previous = starts.mark().pos;
  }
}

/// Finds a key that a map in `node` holds twice (yaml-cpp keeps both and `node[key]` takes the first, so a
/// repeated key would be half-read). Returns "" or "duplicate key 'path.key' (lines A and B)", or, nested deeper
/// than kMaxYamlDepth or holding more than kMaxYamlValues (counted down in `budget`), a message saying so.
std::string findDuplicateKey(const YAML::Node& node, const std::string& path, long* budget, int depth = 0)
{
  if (depth > kMaxYamlDepth)
  {
    return "'" + path.substr(0, 200) + "...' is nested more than " + std::to_string(kMaxYamlDepth) +
           " levels deep: an alias that refers to its own anchor's node?";
  }
  if (--*budget < 0)
  {
    return "more than " + std::to_string(kMaxYamlValues) + " values (at '" + path.substr(0, 200) +
           "'), counting each alias's each time it is used: aliases of lists of aliases?";
  }
  if (node.IsSequence())
  {
    for (std::size_t i = 0; i < node.size(); ++i)
    {
      const std::string error = findDuplicateKey(node[i], path + "[" + std::to_string(i) + "]", budget, depth + 1);
      if (!error.empty())
      {
        return error;
      }
    }
  }
  if (!node.IsMap())
  {
    return "";
  }
  std::vector<std::pair<std::string, int>> seen;  // key and its line (1-based)
  for (const auto& entry : node)
  {
    const std::string key = entry.first.IsScalar() ? entry.first.Scalar() : YAML::Dump(entry.first);
    const std::string name = path.empty() ? key : path + "." + key;
    const int line = entry.first.Mark().line + 1;
    for (const auto& [other, other_line] : seen)
    {
      if (other == key)
      {
        return "duplicate key '" + name + "' (lines " + std::to_string(other_line) + " and " + std::to_string(line) +
               "): give each key once";
      }
    }
    seen.emplace_back(key, line);
    const std::string error = findDuplicateKey(entry.second, name, budget, depth + 1);
    if (!error.empty())
    {
      return error;
    }
  }
  return "";
}

}  // namespace

std::string loadYamlText(const std::string& text, YAML::Node* root)
{
  // Every document, so that one after a `---` line is refused rather than never read (YAML::Load reads the first);
  // an empty one (a `---` at the end) holds nothing to read. First the documents' places, where yaml-cpp may loop.
  refuseEndlessDocuments(text);
  std::vector<YAML::Node> documents = YAML::LoadAll(text);
  documents.erase(std::remove_if(documents.begin(), documents.end(), [](const YAML::Node& d) { return d.IsNull(); }),
                  documents.end());
  *root = documents.empty() ? YAML::Node() : documents.front();
  if (documents.size() > 1)
  {
    return "it holds " + std::to_string(documents.size()) +
           " YAML documents (a line '---' starts each; '...' ends one): give one, the later ones would not be read";
  }
  long budget = kMaxYamlValues;
  return findDuplicateKey(*root, "", &budget);
}

std::string checkYamlFile(const std::string& path)
{
  std::ifstream in(path);
  if (!in)
  {
    return "cannot read '" + path + "'";
  }
  std::ostringstream text;
  text << in.rdbuf();
  try
  {
    YAML::Node root;
    const std::string error = loadYamlText(text.str(), &root);
    return error.empty() ? "" : path + ": " + error;
  }
  catch (const YAML::Exception& e)
  {
    return path + ": YAML error: " + e.what();
  }
}

std::string readNumber(const YAML::Node& node, const std::string& field, double* value)
{
  if (!node.IsScalar() || node.Tag() == "!" || !YAML::convert<double>::decode(node, *value))
  {
    return field + ": expected a number";
  }
  if (!std::isfinite(*value))
  {
    return field + ": must be finite";
  }
  return "";
}

std::string readVector(const YAML::Node& node, const std::string& field, std::size_t size, double* values)
{
  if (!node.IsSequence() || node.size() != size)
  {
    return field + ": expected a list of " + std::to_string(size) + " numbers";
  }
  for (std::size_t i = 0; i < size; ++i)
  {
    const std::string error = readNumber(node[i], field + "[" + std::to_string(i) + "]", &values[i]);
    if (!error.empty())
    {
      return error;
    }
  }
  return "";
}

std::string readText(const YAML::Node& node, const std::string& field, std::string* value)
{
  // A plain scalar that reads as a number is a number (as the parameter server types it); quote it for text.
  double number = 0.0;
  if (!node.IsScalar() || node.Scalar().empty() || (node.Tag() != "!" && YAML::convert<double>::decode(node, number)))
  {
    return field + ": expected a string";
  }
  *value = node.Scalar();
  return "";
}

}  // namespace rov_tether::spec
