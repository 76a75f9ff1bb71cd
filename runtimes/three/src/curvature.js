// How sharply the skin curves at each vertex (crates/pelt-core/src/scene/curvature.rs
// vertex_curvature): the PRT light's terminator band, √(2hκ) in N·L for hair h tall (none on a
// flat surface), is taken per vertex from it, as the preview's rotation pass does.

/**
 * Per vertex, the largest curvature along its triangles' edges, `(n₁ − n₀)·e / |e|²` with unit
 * normals; 0 where flat or concave. `position`, `normal`: flat xyz arrays; `index`: three per
 * triangle.
 */
export function vertexCurvature( position, normal, index ) {

	const count = position.length / 3;
	const unit = new Float32Array( 3 * count );
	for ( let v = 0; v < count; v ++ ) {

		const [ x, y, z ] = normal.subarray( 3 * v, 3 * v + 3 );
		const norm = Math.hypot( x, y, z );
		if ( norm > 0 ) unit.set( [ x / norm, y / norm, z / norm ], 3 * v );

	}

	const curvature = new Float32Array( count );
	const edge = ( a, b ) => {

		let turn = 0;
		let length = 0;
		for ( let c = 0; c < 3; c ++ ) {

			const e = position[ 3 * b + c ] - position[ 3 * a + c ];
			turn += ( unit[ 3 * b + c ] - unit[ 3 * a + c ] ) * e;
			length += e * e;

		}

		const k = length > 0 ? turn / length : 0;
		return Number.isFinite( k ) && k > 0 ? k : 0;

	};

	for ( let t = 0; t + 2 < index.length; t += 3 ) {

		const [ a, b, c ] = [ index[ t ], index[ t + 1 ], index[ t + 2 ] ];
		const [ ab, bc, ca ] = [ edge( a, b ), edge( b, c ), edge( c, a ) ];
		curvature[ a ] = Math.max( curvature[ a ], ab, ca );
		curvature[ b ] = Math.max( curvature[ b ], ab, bc );
		curvature[ c ] = Math.max( curvature[ c ], bc, ca );

	}

	return curvature;

}
