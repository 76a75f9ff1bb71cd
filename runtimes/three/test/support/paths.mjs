// Where the tests find things: the package, the repository, the GLB `make check-gltf` writes
// (env PELT_GLB overrides it; a relative path counts from where npm was started) and the one
// Blender's add-on exports in the user-flow test (env PELT_BLENDER_GLB).

import { dirname, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

export const PACKAGE_DIR = resolve( dirname( fileURLToPath( import.meta.url ) ), '..', '..' );
export const REPO_DIR = resolve( PACKAGE_DIR, '..', '..' );
export const GLB = process.env.PELT_GLB
	? resolve( process.env.INIT_CWD || process.cwd(), process.env.PELT_GLB )
	: resolve( REPO_DIR, 'target/tmp/gltf-check/character_engine.glb' );
// The 30k-triangle character with 32 shells written beside it.
export const BIG_GLB = resolve( dirname( GLB ), 'big_character_engine.glb' );
export const BLENDER_GLB = resolve( process.env.INIT_CWD || process.cwd(), process.env.PELT_BLENDER_GLB || resolve( REPO_DIR, 'target/tmp/three-blender/blender_character.glb' ) );
export const OUT_DIR = resolve( PACKAGE_DIR, 'test', 'out' );
// The wgpu preview's reference scene (reference/make_reference.py's folder; env PELT_REFERENCE).
export const REFERENCE = resolve( process.env.INIT_CWD || process.cwd(), process.env.PELT_REFERENCE || resolve( REPO_DIR, 'target/tmp/three-reference' ) );
