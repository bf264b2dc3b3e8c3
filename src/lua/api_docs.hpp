// The one description of the Lua API: every global Granule adds, every method
// of a simulation, every function of the `granule` library. The same table
// drives help() in the REPL, `granule api` (and so docs/lua_api.md), the arity
// check that every binding gets, the fuzz test that feeds each function bad
// arguments, and the test that fails when an exported function has no entry.
#pragma once

#include <string>
#include <vector>

struct lua_State;

namespace granule::lua {

struct ArgDoc {
  const char* name;  // a table key ("radius"), a position ("1"), or a parameter name
  const char* type;  // number | integer | string | boolean | vector | table | function | list | any
  const char* unit;  // SI unit; "-" dimensionless; "" not a physical quantity
  bool required;
  const char* doc;
};

// How a function is called: f { key = value } (one table), f(a, b) (positional),
// or not at all (a value such as GRANULE_VERSION).
enum class CallForm { table, positional, value };

struct FunctionDoc {
  const char* name;     // "simulation", "sim:fill", "granule.rpm", "granule.vec.add"
  const char* section;  // "global" | "simulation" | "library"
  CallForm form;
  const char* signature;  // how a call reads, with the result after "->"
  const char* doc;        // one line
  std::vector<ArgDoc> args;
  // A valid argument list in the fixture scene of docs/lua_api.md (materials
  // "glass" and "steel", walls "drum" and "floor", particles with ids 0..19, an
  // output with a series "probe"); "" for none. The fuzz test runs it.
  const char* example = "";
  bool open_keys = false;       // table form: keys beyond `args` are accepted
  bool table_optional = false;  // table form: f() is the same as f {}
};

const std::vector<FunctionDoc>& api_docs();
// By full name ("sim:fill"), or by a short name that only one entry ends with ("fill").
const FunctionDoc* find_doc(const std::string& name);
// The nearest documented name, for "did you mean" (empty if none is close).
std::string nearest_doc_name(const std::string& name);
std::string format_help(const FunctionDoc& doc);  // several lines, for the terminal
std::string format_overview();                    // one line per entry
std::string api_markdown();                       // docs/lua_api.md

// help("word"): the entries (API, contact models, diagnostics) whose name or text
// mentions the word, case-insensitively (api_docs_search.cpp).
struct HelpMatch {
  std::string name, doc;
};
std::vector<HelpMatch> search_help(const std::string& word);
std::string format_matches(const std::string& word, const std::vector<HelpMatch>& matches);
// Writes help text to stdout, through $PAGER (or less) when it is longer than the
// terminal; never paged when stdout or stdin is not a terminal.
void show_help_text(const std::string& text);

// Pushes `f` wrapped so that a call with the wrong number of arguments (or a
// method called with '.' instead of ':') is refused before `f` runs.
void push_checked(lua_State* L, const FunctionDoc& doc, int (*f)(lua_State*));
// Registers help(x) and api_reference().
void open_help(lua_State* L);

}  // namespace granule::lua
