// The JSON chunk of a GLB file (glTF 2.0 binary: a 12-byte header, then chunks of length, type,
// data; the first is JSON).

export function glbJson( bytes ) {

	const view = new DataView( bytes.buffer, bytes.byteOffset, bytes.byteLength );
	if ( view.getUint32( 0, true ) !== 0x46546c67 ) throw new Error( 'not a GLB file' );
	const length = view.getUint32( 12, true );
	if ( view.getUint32( 16, true ) !== 0x4e4f534a ) throw new Error( 'the first GLB chunk is not JSON' );
	return JSON.parse( new TextDecoder().decode( bytes.subarray( 20, 20 + length ) ) );

}
