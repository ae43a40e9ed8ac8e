// SPDX-License-Identifier: GPL-3.0-or-later
#include "FormatText.h"
#include "MtgText.h"

#include <plantmorph/TextNumbers.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <sstream>

namespace plantmorph
{

int MtgGraph::FeatureIndex(const std::string& name) const
{
  for (std::size_t f = 0; f < this->features.size(); ++f)
  {
    if (this->features[f].name == name)
    {
      return static_cast<int>(f);
    }
  }
  return -1;
}

int MtgGraph::FinestScale() const
{
  int finest = 0;
  for (const MtgEntity& e : this->entities)
  {
    finest = std::max(finest, e.scale);
  }
  return finest;
}

namespace
{
enum class Section
{
  None,
  Code,
  Classes,
  Description,
  Features,
  Mtg
};

/// The fields of a section line split at blanks (the CLASSES, DESCRIPTION and FEATURES tables).
std::vector<std::string> Words(const std::string& line)
{
  std::istringstream in(line);
  std::vector<std::string> words;
  for (std::string w; in >> w;)
  {
    words.push_back(w);
  }
  return words;
}

std::string Upper(std::string text)
{
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::toupper(c); });
  return text;
}

/// The section a line opens ("NAME:" or "NAME :"), with the text after the colon; Section::None if none.
Section SectionOf(const std::string& trimmed, std::string& rest)
{
  const std::size_t colon = trimmed.find(':');
  if (colon == std::string::npos)
  {
    return Section::None;
  }
  const std::string name = Upper(Trim(trimmed.substr(0, colon)));
  rest = Trim(trimmed.substr(colon + 1));
  return name == "CODE"     ? Section::Code
    : name == "CLASSES"     ? Section::Classes
    : name == "DESCRIPTION" ? Section::Description
    : name == "FEATURES"    ? Section::Features
    : name == "MTG"         ? Section::Mtg
                            : Section::None;
}

/// The reader's state between lines.
class MtgParser
{
public:
  explicit MtgParser(MtgGraph& graph)
    : Graph(graph)
  {
  }

  /// One line; false with Error set on a fault.
  bool Line(const std::string& line, std::size_t number);
  std::string Finish();

  std::string Error;

private:
  bool Fail(const std::string& what)
  {
    this->Error = "line " + std::to_string(this->Number) + ": " + what;
    return false;
  }
  bool TableLine(const std::string& trimmed);
  bool Header(const std::string& line);
  bool Data(const std::string& line);
  bool Code(const std::string& code, std::size_t column, long long& last, long long& support);
  bool Relate(long long from, char relation, const std::string& symbol, long long index, long long& made);
  bool Component(long long from, const std::string& symbol, long long index, long long& made);
  long long Ancestor(long long e, int scale) const;
  bool NewEntity(MtgEntity entity, long long& made);
  bool Values(const std::vector<std::string>& fields, long long entity);
  int ScaleOf(const std::string& symbol) const;

  MtgGraph& Graph;
  Section Current = Section::None;
  bool TableHeaderSeen = false; ///< the current table's column-name line was read
  bool HeaderSeen = false;      ///< the MTG: section's column line was read
  std::size_t Number = 0;
  std::size_t CodeColumns = 0;                      ///< columns before the first feature column
  std::vector<std::pair<std::size_t, int>> Columns; ///< feature columns: (field index, feature)
  std::vector<long long> LastInColumn;              ///< the last entity of the latest line in each column (-1: none)
  std::vector<long long> SupportInColumn;           ///< the finest entity that line stands on (Code's `support`)
};

bool MtgParser::Line(const std::string& line, std::size_t number)
{
  this->Number = number;
  const std::string trimmed = Trim(line);
  if (trimmed.empty() || trimmed[0] == '#')
  {
    return true;
  }
  if (this->Current != Section::Mtg)
  {
    std::string rest;
    const Section opened = SectionOf(trimmed, rest);
    if (opened != Section::None)
    {
      this->Current = opened;
      this->TableHeaderSeen = false;
      if (opened == Section::Code)
      {
        this->Graph.code = rest;
      }
      else if (opened == Section::Mtg && this->Graph.classes.empty())
      {
        return this->Fail("MTG: before any CLASSES (the symbols and their scales)");
      }
      return true;
    }
    return this->TableLine(trimmed);
  }
  return this->HeaderSeen ? this->Data(line) : this->Header(line);
}

bool MtgParser::TableLine(const std::string& trimmed)
{
  const std::vector<std::string> words = Words(trimmed);
  if (words.empty())
  {
    return true; // only white space Trim keeps (form feeds, vertical tabs)
  }
  const bool first = !this->TableHeaderSeen;
  this->TableHeaderSeen = true;
  switch (this->Current)
  {
    case Section::Classes:
    {
      if (first && Upper(words[0]) == "SYMBOL")
      {
        return true;
      }
      double scale = 0.0;
      if (words.size() < 2 || !ParseWholeNumber(words[1], scale) || scale != std::floor(scale) || scale < 0 ||
        scale > kMaxMtgScale)
      {
        return this->Fail("a CLASSES row is SYMBOL SCALE [DECOMPOSITION INDEXATION DEFINITION] with SCALE a whole "
                          "number 0.." +
          std::to_string(kMaxMtgScale) + ": '" + Excerpt(trimmed.data(), trimmed.data() + trimmed.size(), 60) + "'");
      }
      MtgClass c;
      c.symbol = words[0];
      c.scale = static_cast<int>(scale);
      c.decomposition = words.size() > 2 ? words[2] : "";
      c.indexation = words.size() > 3 ? words[3] : "";
      c.definition = words.size() > 4 ? words[4] : "";
      if (this->ScaleOf(c.symbol) >= 0)
      {
        return this->Fail("symbol '" + c.symbol + "' is declared twice in CLASSES");
      }
      this->Graph.classes.push_back(c);
      return true;
    }
    case Section::Description:
      if (!(first && Upper(words[0]) == "LEFT"))
      {
        std::array<std::string, 4> row;
        for (std::size_t k = 0; k < 4 && k < words.size(); ++k)
        {
          row[k] = words[k];
        }
        this->Graph.description.push_back(row);
      }
      return true;
    case Section::Features:
    {
      if (first && Upper(words[0]) == "NAME")
      {
        return true;
      }
      if (words.size() < 2)
      {
        return this->Fail("a FEATURES row is NAME TYPE: '" + words[0] + "' has no type");
      }
      MtgFeature f;
      f.name = words[0];
      f.type = words[1];
      const std::string type = Upper(f.type);
      f.kind = type == "INT" ? MtgFeatureKind::Integer : type == "REAL" ? MtgFeatureKind::Real : MtgFeatureKind::Text;
      if (this->Graph.FeatureIndex(f.name) >= 0)
      {
        return this->Fail("feature '" + f.name + "' is declared twice in FEATURES");
      }
      this->Graph.features.push_back(f);
      return true;
    }
    default:
      return this->Fail("text outside the sections CODE:, CLASSES:, DESCRIPTION:, FEATURES:, MTG:: '" +
        Excerpt(trimmed.data(), trimmed.data() + trimmed.size(), 60) + "'");
  }
}

/// The MTG: section's first line: the code columns, then one column per feature, named as in FEATURES.
bool MtgParser::Header(const std::string& line)
{
  this->HeaderSeen = true;
  const std::vector<std::string> fields = SplitAt(line, '\t');
  this->CodeColumns = 0;
  for (std::size_t i = 1; i < fields.size(); ++i)
  {
    const std::string name = Trim(fields[i]);
    if (name.empty())
    {
      continue;
    }
    const int f = this->Graph.FeatureIndex(name);
    if (f < 0)
    {
      return this->Fail("column '" + name + "' of the MTG: header is not declared in FEATURES");
    }
    if (this->CodeColumns == 0)
    {
      this->CodeColumns = i;
    }
    this->Columns.emplace_back(i, f);
  }
  if (this->CodeColumns == 0)
  {
    this->CodeColumns = std::numeric_limits<std::size_t>::max(); // no features: any indentation
  }
  // The root, '$' at scale 0 (declared or not).
  MtgEntity root;
  root.symbol = "$";
  long long made = 0;
  return this->NewEntity(root, made);
}

int MtgParser::ScaleOf(const std::string& symbol) const
{
  for (const MtgClass& c : this->Graph.classes)
  {
    if (c.symbol == symbol)
    {
      return c.scale;
    }
  }
  return -1;
}

bool MtgParser::NewEntity(MtgEntity entity, long long& made)
{
  if (this->Graph.entities.size() >= kMaxMtgEntities)
  {
    return this->Fail("more than " + std::to_string(kMaxMtgEntities) + " entities");
  }
  entity.line = this->Number;
  made = static_cast<long long>(this->Graph.entities.size());
  this->Graph.entities.push_back(std::move(entity));
  for (std::size_t f = 0; f < this->Graph.features.size(); ++f)
  {
    if (this->Graph.features[f].kind == MtgFeatureKind::Text)
    {
      this->Graph.texts[f].emplace_back();
    }
    else
    {
      this->Graph.numbers[f].push_back(std::numeric_limits<double>::quiet_NaN());
    }
  }
  return true;
}

long long MtgParser::Ancestor(long long e, int scale) const
{
  while (e >= 0 && this->Graph.entities[static_cast<std::size_t>(e)].scale > scale)
  {
    e = this->Graph.entities[static_cast<std::size_t>(e)].complex;
  }
  return e >= 0 && this->Graph.entities[static_cast<std::size_t>(e)].scale == scale ? e : -1;
}

/// A component of `from` one scale finer (`symbol` empty: an unnamed complex '/' skipped): its parent at its scale
/// is the finer entity `from`'s relation waits to carry down (pendingParent), if any.
bool MtgParser::Component(long long from, const std::string& symbol, long long index, long long& made)
{
  std::vector<MtgEntity>& all = this->Graph.entities;
  MtgEntity e;
  e.symbol = symbol;
  e.index = index;
  e.scale = all[static_cast<std::size_t>(from)].scale + 1;
  e.complex = from;
  const long long p = all[static_cast<std::size_t>(from)].pendingParent;
  if (p >= 0)
  {
    const char edge = all[static_cast<std::size_t>(from)].pendingEdge;
    e.edge = edge;
    e.parent = all[static_cast<std::size_t>(p)].scale == e.scale ? p : this->Ancestor(p, e.scale);
    if (all[static_cast<std::size_t>(p)].scale > e.scale)
    {
      e.pendingParent = p, e.pendingEdge = edge;
    }
    all[static_cast<std::size_t>(from)].pendingParent = -1;
  }
  return this->NewEntity(std::move(e), made);
}

/// A new entity `symbol``index` related to `from` by `relation` ('/', '<', '+'). As openalea.mtg reads it, a '/' to a
/// scale not finer than `from`'s makes a component of `from`'s complex one scale coarser (a new plant "/P2" after
/// a plant's internodes), and a '/' that skips scales makes unnamed complexes at the scales between.
bool MtgParser::Relate(long long from, char relation, const std::string& symbol, long long index, long long& made)
{
  const int scale = this->ScaleOf(symbol);
  if (scale < 0)
  {
    return this->Fail("symbol '" + symbol + "' is not declared in CLASSES");
  }
  if (scale == 0)
  {
    return this->Fail("symbol '" + symbol + "' has scale 0, the root's: only entities of scales 1 and more are coded");
  }
  std::vector<MtgEntity>& all = this->Graph.entities;
  if (relation == '/')
  {
    long long complex = all[static_cast<std::size_t>(from)].scale >= scale ? this->Ancestor(from, scale - 1) : from;
    if (complex < 0)
    {
      return this->Fail("'/" + symbol + "': " + all[static_cast<std::size_t>(from)].Label() +
        " has no complex at scale " + std::to_string(scale - 1));
    }
    while (all[static_cast<std::size_t>(complex)].scale + 1 < scale)
    {
      if (!this->Component(complex, std::string(), -1, complex))
      {
        return false;
      }
    }
    return this->Component(complex, symbol, index, made);
  }
  const MtgEntity& source = all[static_cast<std::size_t>(from)];
  if (scale > source.scale)
  {
    return this->Fail(std::string("'") + relation + symbol + "' relates " + source.Label() + " (scale " +
      std::to_string(source.scale) + ") to the finer scale " + std::to_string(scale) + ": use '/' to go finer");
  }
  const long long up = scale == source.scale ? from : this->Ancestor(from, scale);
  if (up < 0)
  {
    return this->Fail(std::string("'") + relation + symbol + "': " + source.Label() + " has no complex at scale " +
      std::to_string(scale));
  }
  MtgEntity e;
  e.symbol = symbol;
  e.index = index;
  e.scale = scale;
  e.edge = relation;
  e.parent = up;
  e.complex = all[static_cast<std::size_t>(up)].complex;
  if (up != from)
  {
    e.pendingParent = from, e.pendingEdge = relation;
  }
  return this->NewEntity(std::move(e), made);
}

/// One code: "[^]rel label rel label ...", starting in `column`; `last` gets its last entity and `support` the finest
/// entity the line stands on (its last, or, when the line went to a coarser scale ("^+B31", "^<U2"), the one it
/// started from: a later '^<S4' in that column follows that one, as openalea.mtg's bracket rewriting does).
bool MtgParser::Code(const std::string& code, std::size_t column, long long& last, long long& support)
{
  std::size_t pos = 0;
  const bool caret = code[0] == '^';
  pos += caret ? 1 : 0;
  long long current = 0; // the root
  const std::size_t from = caret || column == 0 ? column : column - 1;
  const bool known = from < this->LastInColumn.size() && this->LastInColumn[from] >= 0;
  if (!known && (caret || column > 0))
  {
    return this->Fail(caret ? "'^' in column " + std::to_string(column) + ", but no earlier line has a code there"
                            : "a code in column " + std::to_string(column) +
          " without '^' starts from the latest line in column " + std::to_string(column - 1) + ", and there is none");
  }
  current = known ? this->LastInColumn[from] : 0; // column 0 without '^' goes on from the line above, as '^'
  support = known ? this->SupportInColumn[from] : 0;
  const std::vector<MtgEntity>& all = this->Graph.entities;
  bool first = true;
  while (pos < code.size())
  {
    const char r = code[pos];
    if (r == '*')
    {
      return this->Fail("'*' (the dated observations of a dynamic MTG) is not read");
    }
    if (r != '/' && r != '<' && r != '+')
    {
      return this->Fail(
        "expected '/', '<' or '+' at '" + code.substr(pos, 20) + "' in code '" + code.substr(0, 60) + "'");
    }
    const bool range = r == '<' && pos + 1 < code.size() && code[pos + 1] == '<';
    if (r == '+' && pos + 1 < code.size() && code[pos + 1] == '+')
    {
      return this->Fail("'++' (a run of branches) is not read: write each branch on its own line");
    }
    pos += range ? 2 : 1;
    const std::size_t symbolStart = pos;
    while (pos < code.size() && !std::isdigit(static_cast<unsigned char>(code[pos])) && code[pos] != '/' &&
      code[pos] != '<' && code[pos] != '+' && code[pos] != '^')
    {
      ++pos;
    }
    const std::string symbol = code.substr(symbolStart, pos - symbolStart);
    const std::size_t digitStart = pos;
    while (pos < code.size() && std::isdigit(static_cast<unsigned char>(code[pos])))
    {
      ++pos;
    }
    if (symbol.empty() || pos - digitStart > 15)
    {
      return this->Fail("a label is a symbol and an index of at most 15 digits: '" + code.substr(0, 60) + "'");
    }
    const long long index = pos > digitStart ? std::stoll(code.substr(digitStart, pos - digitStart)) : -1;
    const int target = this->ScaleOf(symbol);
    if (first && r != '/' && target > all[static_cast<std::size_t>(current)].scale &&
      all[static_cast<std::size_t>(support)].scale >= target)
    {
      current = this->Ancestor(support, target);
    }
    first = false;
    if (range)
    {
      const MtgEntity& from = this->Graph.entities[static_cast<std::size_t>(current)];
      if (from.symbol != symbol || from.index < 0 || index <= from.index || index - from.index > kMaxMtgRange)
      {
        return this->Fail("'<<" + symbol + std::to_string(index) + "' continues " + from.Label() +
          ": a range needs the same symbol and a larger index, at most " + std::to_string(kMaxMtgRange) + " further");
      }
      for (long long k = from.index + 1; k <= index; ++k)
      {
        if (!this->Relate(current, '<', symbol, k, current))
        {
          return false;
        }
      }
    }
    else if (!this->Relate(current, r, symbol, index, current))
    {
      return false;
    }
  }
  last = current;
  support = all[static_cast<std::size_t>(last)].scale >= all[static_cast<std::size_t>(support)].scale ? last : support;
  return true;
}

bool MtgParser::Values(const std::vector<std::string>& fields, long long entity)
{
  for (const auto& [at, f] : this->Columns)
  {
    const std::string value = at < fields.size() ? Trim(fields[at]) : std::string();
    if (value.empty())
    {
      continue; // a missing value
    }
    const MtgFeature& feature = this->Graph.features[static_cast<std::size_t>(f)];
    if (feature.kind == MtgFeatureKind::Text)
    {
      this->Graph.texts[static_cast<std::size_t>(f)][static_cast<std::size_t>(entity)] = value;
      continue;
    }
    double v = 0.0;
    if (!ParseWholeNumber(value, v) || (feature.kind == MtgFeatureKind::Integer && v != std::floor(v)))
    {
      return this->Fail("feature '" + feature.name + "' is " + feature.type + " but its value is '" +
        Excerpt(value.data(), value.data() + value.size(), 40) + "'");
    }
    this->Graph.numbers[static_cast<std::size_t>(f)][static_cast<std::size_t>(entity)] = v;
  }
  const std::size_t known = this->Columns.empty() ? 0 : this->Columns.back().first + 1;
  for (std::size_t i = known; i < fields.size() && !this->Columns.empty(); ++i)
  {
    if (!Trim(fields[i]).empty())
    {
      return this->Fail("a value in column " + std::to_string(i) + ", after the header's last feature column");
    }
  }
  return true;
}

bool MtgParser::Data(const std::string& line)
{
  const std::vector<std::string> fields = SplitAt(line, '\t');
  std::size_t column = 0;
  while (column < fields.size() && Trim(fields[column]).empty())
  {
    ++column;
  }
  if (column >= this->CodeColumns)
  {
    return this->Fail("no entity code in the first " + std::to_string(this->CodeColumns) +
      " columns (the columns before the header's first feature)");
  }
  for (std::size_t i = column + 1; i < fields.size() && i < this->CodeColumns; ++i)
  {
    if (!Trim(fields[i]).empty())
    {
      return this->Fail("two codes on one line (columns " + std::to_string(column) + " and " + std::to_string(i) + ")");
    }
  }
  long long last = -1, support = 0;
  if (!this->Code(Trim(fields[column]), column, last, support) || !this->Values(fields, last))
  {
    return false;
  }
  if (column >= this->LastInColumn.size())
  {
    this->LastInColumn.resize(column + 1, -1);
    this->SupportInColumn.resize(column + 1, 0);
  }
  this->LastInColumn[column] = last;
  this->SupportInColumn[column] = support;
  return true;
}

std::string MtgParser::Finish()
{
  if (!this->HeaderSeen)
  {
    return "no MTG: section (a FORM-A file has CODE:, CLASSES:, DESCRIPTION:, FEATURES: and MTG:)";
  }
  if (this->Graph.entities.size() < 2)
  {
    return "the MTG: section has no entity";
  }
  return {};
}
} // namespace

std::string ReadMtg(std::istream& in, MtgGraph& graph)
{
  graph = MtgGraph();
  LineReader lines(in, kMaxMtgLineLength);
  MtgParser parser(graph);
  std::string line;
  bool first = true;
  while (lines.Next(line))
  {
    if (first && line.compare(0, 3, "\xEF\xBB\xBF") == 0)
    {
      line.erase(0, 3); // a UTF-8 byte order mark
    }
    first = false;
    if (graph.numbers.size() != graph.features.size())
    {
      graph.numbers.resize(graph.features.size());
      graph.texts.resize(graph.features.size());
    }
    if (!parser.Line(line, lines.Number()))
    {
      graph = MtgGraph();
      return parser.Error;
    }
  }
  std::string error = lines.Error().empty() ? parser.Finish() : lines.Error();
  if (!error.empty())
  {
    graph = MtgGraph();
  }
  return error;
}

} // namespace plantmorph
