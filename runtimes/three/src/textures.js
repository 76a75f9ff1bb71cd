// The extension's textures (docs/export.md, "Images"): ordinary glTF textures, loaded through the
// parser so that GLTFLoader decodes each image once. Each is cloned before its sampling is set:
// the skin's material may share the image with other settings.

import {
	ClampToEdgeWrapping,
	LinearFilter,
	LinearMipmapLinearFilter,
	NoColorSpace,
	RepeatWrapping,
	SRGBColorSpace,
} from 'three';

function configured( texture, { colorSpace, wrapS, wrapT, mipmaps } ) {

	const t = texture.clone();
	t.colorSpace = colorSpace;
	t.flipY = false;
	t.wrapS = wrapS;
	t.wrapT = wrapT;
	t.magFilter = LinearFilter;
	t.minFilter = mipmaps ? LinearMipmapLinearFilter : LinearFilter;
	t.generateMipmaps = mipmaps;
	t.needsUpdate = true;
	return t;

}

// The atlases are addressed cell by cell: clamped, bilinear, one level (a mip level would blend
// neighbouring cells).
const ATLAS = { wrapS: ClampToEdgeWrapping, wrapT: ClampToEdgeWrapping, mipmaps: false };

/**
 * The textures of one extension object, configured: sRGB colors (skin, shell atlas, fin),
 * linear data (tangents, transfer); the fin texture repeats along u, clamps along v and has
 * mipmaps (fins.wgsl reads it at a chosen level).
 */
export async function loadFurTextures( parser, ext ) {

	const get = ( index ) => parser.getDependency( 'texture', index ).then( ( texture ) => {

		if ( ! texture ) throw new Error( `PELT_shell_fur: texture ${index} did not load` );
		return texture;

	} );
	const t = ext.textures;
	const [ skin, shellsAtlas, tangentsAtlas, fin, ...transfer ] = await Promise.all(
		[ t.skin, t.shells_atlas, t.tangents_atlas, t.fin, ...t.transfer ].map( get ) );
	return {
		skin: configured( skin, { colorSpace: SRGBColorSpace, wrapS: RepeatWrapping, wrapT: RepeatWrapping, mipmaps: true } ),
		shellsAtlas: configured( shellsAtlas, { colorSpace: SRGBColorSpace, ...ATLAS } ),
		tangentsAtlas: configured( tangentsAtlas, { colorSpace: NoColorSpace, ...ATLAS } ),
		fin: configured( fin, { colorSpace: SRGBColorSpace, wrapS: RepeatWrapping, wrapT: ClampToEdgeWrapping, mipmaps: true } ),
		transfer: transfer.map( ( texture ) => configured( texture, { colorSpace: NoColorSpace, ...ATLAS } ) ),
	};

}
