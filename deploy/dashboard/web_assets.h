#pragma once
// The dashboard's page, script and style sheet (deploy/dashboard/web/), compiled into the
// program by cmake/SricsEmbedFiles.cmake so it serves them from anywhere, offline.

namespace srics::dashboard {

extern const char* const kIndexHtml;     // web/index.html
extern const char* const kDashboardJs;   // web/dashboard.js
extern const char* const kDashboardCss;  // web/dashboard.css

}  // namespace srics::dashboard
