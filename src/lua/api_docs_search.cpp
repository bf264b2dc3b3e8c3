// help("word"): every entry of the API, every contact model and every diagnostic
// whose name or text mentions the word; and the pager help() shows long text through.
#include <fmt/format.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>

#include "contact/model_docs.hpp"
#include "contact/models.hpp"
#include "hooks/diagnostic.hpp"
#include "lua/api_docs.hpp"

namespace granule::lua {

namespace {

std::string lowered(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool mentions(const std::string& text, const std::string& word_lowered) {
  return lowered(text).find(word_lowered) != std::string::npos;
}

// The first line of a doc (a model's doc may run long), cut for a one-line listing.
std::string summary(const std::string& doc) {
  std::string s = doc.substr(0, doc.find('\n'));
  return s.size() > 90 ? s.substr(0, 87) + "..." : s;
}

}  // namespace

std::vector<HelpMatch> search_help(const std::string& word) {
  std::vector<HelpMatch> out;
  const std::string w = lowered(word);
  if (w.empty()) return out;
  for (const auto& d : api_docs()) {
    if (std::string(d.name) == "help") continue;  // its own text names examples, not topics
    bool hit = mentions(d.name, w) || mentions(d.signature, w) || mentions(d.doc, w);
    for (const auto& a : d.args) hit = hit || mentions(a.name, w) || mentions(a.doc, w);
    if (hit) out.push_back({d.name, summary(d.doc)});
  }
  for (const auto& m : documented_models()) {
    bool hit = mentions(m.name, w) || mentions(m.doc, w);
    for (const auto& p : m.parameters) hit = hit || mentions(p.name, w) || mentions(p.doc, w);
    if (hit) out.push_back({m.name + " (contact model)", summary(m.doc)});
  }
  for (const auto& d : diagnostic_catalogue()) {
    bool hit = mentions(d.name, w) || mentions(d.doc, w);
    for (const auto& o : d.options) hit = hit || mentions(o.key, w) || mentions(o.doc, w);
    if (hit) out.push_back({d.name + " (diagnostic)", summary(d.doc)});
  }
  return out;
}

std::string format_matches(const std::string& word, const std::vector<HelpMatch>& matches) {
  std::string out = fmt::format("{} entr{} mention '{}' (help('name') for one):\n", matches.size(),
                                matches.size() == 1 ? "y" : "ies", word);
  std::size_t width = 0;
  for (const auto& m : matches) width = std::max(width, m.name.size());
  for (const auto& m : matches) out += fmt::format("  {:<{}}  {}\n", m.name, width, m.doc);
  return out;
}

void show_help_text(const std::string& text) {
  // Only a person at a terminal gets a pager; a pipe, a file or a test gets the text.
  if (isatty(STDOUT_FILENO) && isatty(STDIN_FILENO)) {
    int rows = 24;
    winsize ws{};
    if (ioctl(STDOUT_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_row > 0) rows = ws.ws_row;
    const auto lines = std::count(text.begin(), text.end(), '\n');
    if (lines >= rows - 1) {
      const char* pager = std::getenv("PAGER");
      // less: -F quits when the text fits after all, -R keeps colours, -X leaves it on screen.
      std::string command = pager && *pager ? pager : "less -FRX";
      std::fflush(stdout);
      if (FILE* p = popen(command.c_str(), "w")) {
        std::fwrite(text.data(), 1, text.size(), p);
        if (pclose(p) == 0) return;
        // The pager could not run (not installed): the text as it is, below.
      }
    }
  }
  std::fputs(text.c_str(), stdout);
  std::fflush(stdout);
}

}  // namespace granule::lua
