/* For bench/leak_check.sh only: a dlclose() that leaves the library loaded. libEGL_mesa
 * unloads Mesa's driver (swrast_dri.so) when the display is terminated, while memory the driver
 * allocated is still referenced from its globals; once unmapped, LeakSanitizer sees that
 * memory as leaked from "<unknown module>". Kept loaded, the driver's globals still reach it,
 * and any real leak would have a stack with names. LD_PRELOADed into the checked processes. */
int dlclose(void* handle) {
  (void)handle;
  return 0;
}
