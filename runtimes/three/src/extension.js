// Reading the PELT_shell_fur extension (docs/export.md, "glTF: `engine` mode and the
// `PELT_shell_fur` extension"; schema docs/schema/PELT_shell_fur.schema.json).

export const EXTENSION_NAME = 'PELT_shell_fur';

// GLTFLoader's own names for the standard attributes; every other attribute keeps its glTF name
// lower-cased (`_PELT_LENGTH` becomes `_pelt_length`), as its addPrimitiveAttributes does.
const THREE_ATTRIBUTES = {
	POSITION: 'position',
	NORMAL: 'normal',
	TANGENT: 'tangent',
	TEXCOORD_0: 'uv',
	TEXCOORD_1: 'uv1',
	TEXCOORD_2: 'uv2',
	TEXCOORD_3: 'uv3',
	COLOR_0: 'color',
	WEIGHTS_0: 'skinWeight',
	JOINTS_0: 'skinIndex',
};

/** The name GLTFLoader gives the glTF vertex attribute `name` on a BufferGeometry. */
export function threeAttributeName( name ) {

	return THREE_ATTRIBUTES[ name ] || name.toLowerCase();

}

const ATTRIBUTE_KEYS = [ 'uv', 'color', 'length', 'comb', 'dpdu', 'dpdv' ];
const TEXTURE_KEYS = [ 'skin', 'shells_atlas', 'tangents_atlas', 'fin' ];

function fail( where, message ) {

	throw new Error( `${EXTENSION_NAME}: ${where} ${message}` );

}

/**
 * Checks what the runtime relies on in one extension object (the exporter's tests check the rest
 * against the schema) and returns it. `where` names the primitive in messages.
 */
export function checkExtension( ext, where ) {

	if ( ext === null || typeof ext !== 'object' ) fail( where, 'is not an object' );
	if ( ext.version !== 1 ) fail( where, `has version ${ext.version}, this runtime reads 1` );
	const s = ext.stack;
	if ( ! s || typeof s !== 'object' ) fail( where, 'has no stack' );
	for ( const key of [ 'layers', 'shells', 'layer_spacing', 'fur_depth', 'uv_scale' ] ) {

		if ( typeof s[ key ] !== 'number' || ! Number.isFinite( s[ key ] ) ) fail( where, `stack.${key} must be a number` );

	}

	if ( ! Array.isArray( s.shell_layers ) || s.shell_layers.length !== s.shells ) {

		fail( where, 'stack.shell_layers must list one layer per shell' );

	}

	for ( const l of s.shell_layers ) {

		if ( ! Number.isInteger( l ) || l < 1 || l >= s.layers ) fail( where, `stack.shell_layers holds ${l}, outside 1..${s.layers - 1}` );

	}

	const a = s.atlas;
	if ( ! a || ! ( a.columns * a.rows >= s.layers ) || ! ( a.tile > 0 ) ) fail( where, 'stack.atlas does not hold every layer' );
	if ( a.width !== a.columns * a.tile || a.height !== a.rows * a.tile ) fail( where, 'stack.atlas size is not columns x rows tiles' );
	for ( const key of ATTRIBUTE_KEYS ) {

		if ( typeof ext.attributes?.[ key ] !== 'string' ) fail( where, `attributes.${key} must name an attribute` );

	}

	for ( const key of TEXTURE_KEYS ) {

		if ( ! Number.isInteger( ext.textures?.[ key ] ) ) fail( where, `textures.${key} must be a texture index` );

	}

	const transfer = s.transfer;
	const transferTextures = ext.textures.transfer;
	if ( ! Array.isArray( transferTextures ) ) fail( where, 'textures.transfer must be a list' );
	if ( transfer ) {

		const n = transfer.order * transfer.order;
		if ( transfer.coefficients !== n || transfer.scale.length !== n || transfer.bias.length !== n ) {

			fail( where, 'stack.transfer must give order² coefficients, scales and biases' );

		}

		if ( transfer.textures !== Math.ceil( n / 4 ) || transferTextures.length !== transfer.textures ) {

			fail( where, 'stack.transfer.textures must be ⌈order² / 4⌉ and match textures.transfer' );

		}

	} else if ( transferTextures.length !== 0 ) {

		fail( where, 'lists transfer textures without stack.transfer' );

	}

	if ( ! Array.isArray( ext.fallback ) ) fail( where, 'fallback must be a list' );
	const g = ext.guardHairs;
	if ( g !== undefined && ( ! Number.isInteger( g?.primitive ) || typeof g.radius !== 'string' || ! Number.isInteger( g.strands ) ) ) {

		fail( where, 'guardHairs must give the LINES primitive, the strand count and the radius attribute' );

	}

	return ext;

}

/** Every `[meshIndex, primitiveIndex, extension]` of the glTF JSON that carries the extension. */
export function furPrimitives( json ) {

	const found = [];
	( json.meshes || [] ).forEach( ( mesh, m ) => {

		( mesh.primitives || [] ).forEach( ( primitive, p ) => {

			const ext = primitive.extensions?.[ EXTENSION_NAME ];
			if ( ext !== undefined ) {

				found.push( [ m, p, checkExtension( ext, `meshes[${m}].primitives[${p}]` ) ] );

			}

		} );

	} );
	return found;

}
