// The contact models as the documentation shows them, written from the model
// registry (models.hpp) and its parameter descriptors (parameters.hpp), so that
// help() in the REPL, `granule models`, docs/lua_api.md and the parameter
// tables of docs/contact_models.md cannot drift from what the code accepts.
#pragma once

#include <string>
#include <vector>

#include "contact/models.hpp"

namespace granule {

// What the documentation shows: the models a scene names (registry order,
// without their rolling variants), then the rolling-resistance term as an
// entry of its own, "rolling" (its parameters are accepted by every model).
std::vector<ContactModelInfo> documented_models();

// The model names a scene may give, in registry order, joined by `separator`.
std::string contact_model_names(const std::string& separator);
// The names of the models that offer a batched kernel in `dimension` (contact_batch.hpp).
std::string batched_model_names(const std::string& separator, int dimension);

// A parameter's valid range as an interval, e.g. "(0, 1]" or "[0, inf)".
std::string parameter_range(const ParamSpec& p);
// "required" or the default value.
std::string parameter_default(const ParamSpec& p);

// For the terminal: the model's name and doc, then one line per parameter
// (name, unit, default, range, doc).
std::string format_model_help(const ContactModelInfo& m);
std::string format_models_help();  // every registered model

// Markdown: one bullet per model with its parameters, for docs/lua_api.md.
std::string models_markdown_list();
// Markdown: the table of one model's parameters (docs/contact_models.md).
std::string model_parameter_table(const ContactModelInfo& m);

// The markers around each generated table in docs/contact_models.md.
std::string table_begin_marker(const std::string& model);
extern const char* const table_end_marker;

// `page` with the text between each model's markers replaced by its table.
// Throws InputError naming `source` and the line for an unknown model, a
// marker without its end, a model given twice, or a registered model the page
// has no table for.
std::string regenerate_model_tables(const std::string& page, const std::string& source);
// The same for the page in the file `path` (an error names the file).
std::string regenerate_model_tables_in(const std::string& path);

}  // namespace granule
