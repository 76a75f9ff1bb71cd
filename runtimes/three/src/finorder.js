// The fins' draw order, farthest first (crates/pelt-core/src/scene/fin_cull.rs
// `visible_indices`): the fins are blended "over" without writing depth, so drawn in any other
// order a farther fin covers a nearer one where they overlap. Past the skin's outline, where the
// eye looks through the lit fins in front of the limb to the unlit ones behind it, that had drawn
// the dark ones on top (a hard, dark ring around the skin on long fur). Sorted on the CPU by the
// fins' rest-pose centers, as the renderer does by its deformed ones: a skinned pose that moves
// fins past one another is not followed (sorting skinned centers would mean skinning on the CPU
// every frame).

// Distance steps of the sort: fins nearer each other than 1/65536 of the range between the
// nearest and the farthest keep their order by fin. One counting sort over them (linear in the
// fins: a frame that orbits the fur re-sorts every time).
const STEPS = 65536;

/**
 * Each fin's center, the midpoint of its edge at the skin, from fin quad corners laid out as
 * geometry.js finGeometry lays them (corners 4f and 4f + 1: the edge's ends at the skin).
 */
export function finCenters( positions, fins ) {

	const centers = new Float32Array( 3 * fins );
	for ( let f = 0; f < fins; f ++ ) {

		for ( let k = 0; k < 3; k ++ ) centers[ 3 * f + k ] = 0.5 * ( positions[ 12 * f + k ] + positions[ 12 * f + 3 + k ] );

	}

	return centers;

}

/**
 * Writes into `indices` the quads' triangles ([0, 1, 3, 0, 3, 2] per fin, as finGeometry) farthest
 * from `eye` first, a tie to the lower fin. `eye` is homogeneous in the centers' space: w = 1 a
 * position (the squared distance orders), w = 0 a direction toward the viewer (the depth along it
 * orders: an orthographic camera).
 */
export function backToFront( centers, eye, indices ) {

	const fins = centers.length / 3;
	const distance = new Float64Array( fins );
	let near = Infinity;
	let far = - Infinity;
	for ( let f = 0; f < fins; f ++ ) {

		const x = centers[ 3 * f ];
		const y = centers[ 3 * f + 1 ];
		const z = centers[ 3 * f + 2 ];
		const d = eye[ 3 ] === 0
			? - ( x * eye[ 0 ] + y * eye[ 1 ] + z * eye[ 2 ] )
			: ( eye[ 0 ] - x ) ** 2 + ( eye[ 1 ] - y ) ** 2 + ( eye[ 2 ] - z ) ** 2;
		distance[ f ] = d;
		near = Math.min( near, d );
		far = Math.max( far, d );

	}

	// Counting sort, farthest step first; within a step the fins in ascending order (stable).
	const scale = far > near ? STEPS / ( far - near ) : 0;
	const step = new Uint32Array( fins );
	const starts = new Uint32Array( STEPS + 1 );
	for ( let f = 0; f < fins; f ++ ) {

		step[ f ] = Math.min( STEPS - 1, Math.floor( ( far - distance[ f ] ) * scale ) );
		starts[ step[ f ] + 1 ] ++;

	}

	for ( let k = 1; k <= STEPS; k ++ ) starts[ k ] += starts[ k - 1 ];
	const order = new Uint32Array( fins );
	for ( let f = 0; f < fins; f ++ ) order[ starts[ step[ f ] ] ++ ] = f;

	for ( let k = 0; k < fins; k ++ ) {

		const base = 4 * order[ k ];
		const at = 6 * k;
		indices[ at ] = base;
		indices[ at + 1 ] = base + 1;
		indices[ at + 2 ] = base + 3;
		indices[ at + 3 ] = base;
		indices[ at + 4 ] = base + 3;
		indices[ at + 5 ] = base + 2;

	}

	return indices;

}
