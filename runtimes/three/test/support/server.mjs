// A static HTTP server for the browser test: the package directory at `/` (the example, src/ and
// node_modules/ for the import map), model files at the paths `models` names (`/model.glb`,
// ...) and a folder at `/reference/` (the wgpu preview's reference scene), when given.

import { createReadStream } from 'node:fs';
import { stat } from 'node:fs/promises';
import { createServer } from 'node:http';
import { extname, join, normalize, sep } from 'node:path';

const TYPES = {
	'.html': 'text/html; charset=utf-8',
	'.js': 'text/javascript; charset=utf-8',
	'.mjs': 'text/javascript; charset=utf-8',
	'.json': 'application/json',
	'.glb': 'model/gltf-binary',
	'.png': 'image/png',
};

/** Serves `root`, `models` ({url path: file}) and `reference` on 127.0.0.1 at a free port; resolves to {url, close()}. */
export function serve( root, models, reference = null ) {

	const server = createServer( async ( request, response ) => {

		const path = decodeURIComponent( new URL( request.url, 'http://localhost' ).pathname );
		const referenced = reference && path.startsWith( '/reference/' );
		const base = referenced ? reference : root;
		const model = Object.hasOwn( models, path ) ? models[ path ] : null;
		const file = model ?? normalize( join( base, referenced ? path.slice( 10 ) : path ) );
		const inside = model !== null || file.startsWith( base + sep );
		const info = inside ? await stat( file ).catch( () => null ) : null;
		if ( ! info?.isFile() ) {

			response.writeHead( 404 ).end( 'not found' );
			return;

		}

		response.writeHead( 200, {
			'content-type': TYPES[ extname( file ) ] || 'application/octet-stream',
			'content-length': info.size,
			'cache-control': 'no-store',
		} );
		createReadStream( file ).pipe( response );

	} );
	return new Promise( ( resolve, reject ) => {

		server.once( 'error', reject );
		server.listen( 0, '127.0.0.1', () => resolve( {
			url: `http://127.0.0.1:${server.address().port}`,
			close: () => new Promise( ( done ) => server.close( done ) ),
		} ) );

	} );

}
