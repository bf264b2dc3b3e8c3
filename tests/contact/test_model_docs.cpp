// The model documentation is written from the registry: every registered
// model and every parameter descriptor (name, unit, default, range, doc)
// reaches help(), `granule models`, docs/lua_api.md and the tables of
// docs/contact_models.md, and the page generator refuses a page that lacks a
// model or names one that does not exist.
#include <fmt/format.h>

#include <catch2/catch.hpp>
#include <lua.hpp>
#include <string>

#include "contact/model_docs.hpp"
#include "core/errors.hpp"
#include "lua/api_docs.hpp"
#include "lua/scene.hpp"

using namespace granule;

namespace {

// A page with an empty table block for each registered model, as a new page would start.
std::string page_with_markers() {
  std::string page = "# Models\n\nsome prose\n";
  for (const auto& m : documented_models())
    page += "\n## " + m.name + "\n\n" + table_begin_marker(m.name) + "\n" + table_end_marker + "\n";
  return page;
}

std::string error_of(const std::string& page) {
  try {
    regenerate_model_tables(page, "page.md");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("model docs: help for sim:contact lists every model with every descriptor field",
          "[docs][models]") {
  const auto catalogue = contact_model_catalogue();
  REQUIRE(catalogue.size() == static_cast<std::size_t>(contact_model_count));
  const lua::FunctionDoc* contact = lua::find_doc("sim:contact");
  REQUIRE(contact != nullptr);
  const std::string help = lua::format_help(*contact);
  const std::string markdown = lua::api_markdown();
  const std::string models = format_models_help();
  // The `model` argument names exactly the registered models, in registry order.
  std::string names;
  for (const auto& a : contact->args)
    if (std::string(a.name) == "model") names = a.doc;
  CHECK(names == contact_model_names(" | "));
  // The rolling variants are not named: the rolling term is documented once.
  for (const auto& m : catalogue)
    if (m.rolling) CHECK(names.find(m.name) == std::string::npos);
  for (const auto& m : documented_models()) {
    INFO("model " << m.name);
    if (!m.rolling) CHECK_THAT(names, Catch::Contains(m.name));
    CHECK_THAT(help, Catch::Contains(m.name + ": " + m.doc));
    CHECK_THAT(markdown, Catch::Contains("- `" + m.name + "`: " + m.doc));
    const std::string one = format_model_help(m);
    CHECK_THAT(models, Catch::Contains(one));
    REQUIRE(!m.parameters.empty());
    for (const auto& p : m.parameters) {
      INFO("parameter " << p.name);
      // One line of the model's help holds the parameter's five fields.
      const std::string line_start = std::string("    ") + p.name + " ";
      const auto at = one.find(line_start);
      REQUIRE(at != std::string::npos);
      const std::string line = one.substr(at, one.find('\n', at) - at);
      CHECK_THAT(line, Catch::Contains(std::string("[") + p.unit + "]"));
      CHECK_THAT(line, Catch::Contains(parameter_default(p)));
      CHECK_THAT(line, Catch::Contains(parameter_range(p)));
      CHECK_THAT(line, Catch::Contains(p.doc));
      CHECK_THAT(markdown, Catch::Contains(std::string("`") + p.name + "` [" + p.unit + "]"));
    }
  }
}

TEST_CASE("model docs: ranges and defaults read as resolve_parameters checks them",
          "[docs][models]") {
  const ParamSpec open_low{"x", "-", required, 0, 1, false, "doc"};
  const ParamSpec closed_low{"y", "N/m", 0.25, -1, unbounded, true, "doc"};
  CHECK(parameter_range(open_low) == "(0, 1]");
  CHECK(parameter_range(closed_low) == "[-1, inf)");
  CHECK(parameter_default(open_low) == "required");
  CHECK(parameter_default(closed_low) == "0.25");
  // The same bounds refuse and accept as the text says.
  CHECK_THROWS_AS(resolve_parameters({open_low}, {{"x", 0.0}}, "t"), InputError);
  CHECK_NOTHROW(resolve_parameters({open_low}, {{"x", 1.0}}, "t"));
  CHECK_NOTHROW(resolve_parameters({closed_low}, {{"y", -1.0}}, "t"));
  CHECK_THROWS_AS(resolve_parameters({closed_low}, {{"y", -1.5}}, "t"), InputError);
}

TEST_CASE("model docs: the page generator fills each model's table and refuses a wrong page",
          "[docs][models]") {
  const std::string page = page_with_markers();
  const std::string filled = regenerate_model_tables(page, "page.md");
  for (const auto& m : documented_models()) {
    INFO("model " << m.name);
    CHECK_THAT(filled, Catch::Contains(table_begin_marker(m.name) + "\n" +
                                       model_parameter_table(m) + table_end_marker));
    for (const auto& p : m.parameters)
      CHECK_THAT(model_parameter_table(m),
                 Catch::Contains(fmt::format("| `{}` | {} | {} | {} |", p.name, p.unit,
                                             parameter_default(p), parameter_range(p))));
  }
  CHECK_THAT(filled, Catch::Contains("some prose"));
  // Regenerating a generated page changes nothing; a stale table is replaced.
  CHECK(regenerate_model_tables(filled, "page.md") == filled);
  std::string stale = filled;
  const std::string row = "| `friction` |";
  stale.replace(stale.find(row), row.size(), "| `friktion` |");
  CHECK(regenerate_model_tables(stale, "page.md") == filled);

  // A registered model without a table.
  const std::string first = contact_model_catalogue().front().name;
  std::string missing = page;
  missing.erase(missing.find(table_begin_marker(first)), table_begin_marker(first).size() + 1);
  missing.erase(missing.find(table_end_marker), std::string(table_end_marker).size() + 1);
  CHECK_THAT(error_of(missing),
             Catch::Contains("no parameter table for contact model '" + first + "'"));
  // A marker naming no registered model, with its line.
  CHECK_THAT(error_of("title\n" + table_begin_marker("no_such_model") + "\n" + table_end_marker +
                      "\n" + page),
             Catch::Contains("page.md:2: table marker for unknown contact model 'no_such_model'"));
  // A table without its end, a stray end, a model twice.
  CHECK_THAT(error_of(table_begin_marker(first) + "\n"), Catch::Contains("page.md:1:"));
  CHECK_THAT(error_of(std::string(table_end_marker) + "\n" + page),
             Catch::Contains("without a BEGIN marker"));
  CHECK_THAT(error_of(page + table_begin_marker(first) + "\n" + table_end_marker + "\n"),
             Catch::Contains("a second table for contact model '" + first + "'"));
  CHECK_THROWS_WITH(regenerate_model_tables_in("/nonexistent/contact_models.md"),
                    Catch::Contains("cannot read '/nonexistent/contact_models.md'"));
}

TEST_CASE("model docs: help() knows the models by name and suggests the nearest",
          "[docs][models]") {
  lua::SceneContext ctx;
  lua_State* L = lua::new_state(&ctx);
  auto run = [L](const std::string& code) {
    std::string err;
    if (luaL_dostring(L, code.c_str()) != LUA_OK) {
      err = lua_tostring(L, -1) ? lua_tostring(L, -1) : "?";
      lua_pop(L, 1);
    }
    return err;
  };
  for (const auto& m : contact_model_catalogue()) CHECK(run("help('" + m.name + "')") == "");
  CHECK(run("help('models')") == "");
  CHECK_THAT(run("help('walton_brawn')"), Catch::Contains("did you mean 'walton_braun'"));
  CHECK_THAT(run("help('modles')"), Catch::Contains("did you mean 'models'"));
  lua_close(L);
}
