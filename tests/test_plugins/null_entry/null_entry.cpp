// Deliberately broken (loader test): the exported alias gdsmc_plugin_entry, which BOOST_DLL_ALIAS
// would point at the entry function, is null. The symbol exists, so the host calls it: SIGSEGV.
extern "C" __attribute__((visibility("default"))) const void* const gdsmc_plugin_entry = nullptr;
