// The report page: an offline index.html in a run, sweep, stability or bench folder.
//
// The page itself is static (report/ in the data folder: index.html, its scripts and styles, and
// three.js copied in at build time); what changes from folder to folder is one data file,
// report/data.js, holding the folder's summaries and CSV tables, and, for a run that kept frames,
// one small script per backend and sample (report/frames/<backend>/<NNNNN>.js) that the page
// loads when it first shows that frame. Scripts, not JSON files: a page opened from file:// may
// load scripts but may not fetch files.
#pragma once

#include <string>
#include <vector>

namespace chainmail {

// writes index.html and report/ into `folder`, a folder made by `command` (run, sweep,
// stability or bench) and whose files are all there; returns the files written, relative to
// `folder`. Everything is read and checked first: a folder chainmail did not write, a missing or
// corrupt summary.json, frames that do not match the summary throw UsageError (exit 2) naming the
// file, and nothing is written.
std::vector<std::string> write_report(const std::string& folder, const std::string& command);

// write_report for a command that just wrote `folder` (run --report, bench): a page that cannot be
// written is one line on stderr, never the loss of the results beside it
void write_report_beside(const std::string& folder, const std::string& command);

// chainmail report DIR: write_report on a committed folder, its manifest updated to list the page
int report_command(const std::string& folder);

}  // namespace chainmail
