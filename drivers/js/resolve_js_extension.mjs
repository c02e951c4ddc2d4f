// A Node.js module resolve hook: quickhull3d 3.x ships ES modules that import their own files and
// gl-vec3's without the ".js" extension ("./QuickHull", "gl-vec3/dot"), which Node's ES module
// resolution refuses (ERR_MODULE_NOT_FOUND).  Retry such a specifier with ".js" added.
export async function resolve(specifier, context, nextResolve) {
  try {
    return await nextResolve(specifier, context);
  } catch (err) {
    if (err?.code !== 'ERR_MODULE_NOT_FOUND' || specifier.endsWith('.js')) throw err;
    return nextResolve(`${specifier}.js`, context);
  }
}
