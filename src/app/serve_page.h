#pragma once
// The page `nsf serve` answers at GET / (web/serve.html, embedded at build time).
namespace nsf::app {
const char* serve_page();
}
