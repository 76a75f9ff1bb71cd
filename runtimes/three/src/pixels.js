// Reading an image's exact RGBA bytes in the browser, for the fins' mean transfer per layer
// (sh.js `layerMeans`). A 2D canvas stores premultiplied colors and would round the transfer
// coefficients kept in alpha; a WebGL2 texture read back through a framebuffer returns the
// bytes as decoded (GLTFLoader's image bitmaps are neither premultiplied nor color converted).

/** The RGBA bytes of each image (ImageBitmap, HTMLImageElement or canvas), rows from the top. */
export function imageBytes( images ) {

	const canvas = typeof OffscreenCanvas !== 'undefined' ? new OffscreenCanvas( 1, 1 ) : document.createElement( 'canvas' );
	const gl = canvas.getContext( 'webgl2', { premultipliedAlpha: false } );
	if ( ! gl ) throw new Error( 'PELT_shell_fur: reading the transfer textures needs WebGL 2' );
	try {

		gl.pixelStorei( gl.UNPACK_FLIP_Y_WEBGL, false );
		gl.pixelStorei( gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, false );
		gl.pixelStorei( gl.UNPACK_COLORSPACE_CONVERSION_WEBGL, gl.NONE );
		gl.pixelStorei( gl.PACK_ALIGNMENT, 1 );
		const texture = gl.createTexture();
		const framebuffer = gl.createFramebuffer();
		gl.bindTexture( gl.TEXTURE_2D, texture );
		gl.bindFramebuffer( gl.FRAMEBUFFER, framebuffer );
		return images.map( ( image ) => {

			gl.texImage2D( gl.TEXTURE_2D, 0, gl.RGBA8, gl.RGBA, gl.UNSIGNED_BYTE, image );
			gl.framebufferTexture2D( gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, texture, 0 );
			const bytes = new Uint8Array( image.width * image.height * 4 );
			// Texture row 0 is the image's first (top) row, and so is the framebuffer's row 0.
			gl.readPixels( 0, 0, image.width, image.height, gl.RGBA, gl.UNSIGNED_BYTE, bytes );
			return bytes;

		} );

	} finally {

		gl.getExtension( 'WEBGL_lose_context' )?.loseContext();

	}

}
