// @pelt/three-fur: a three.js runtime for Pelt's PELT_shell_fur glTF extension.

export { PeltShellFurPlugin } from './plugin.js';
export { PeltFur } from './fur.js';
export { EXTENSION_NAME, threeAttributeName } from './extension.js';
export { DEFAULT_LIGHTING } from './lighting.js';
