// The fins' random texture offsets (docs/export.md, "Conventions": Fins, `u0` random in [0, 1)):
// a counter-based generator, so fin k gets the same offset whatever the other edges are.

/** Fixed seed of the fin offsets: the fins look the same on every load. */
export const FIN_SEED = 0x5045_4c54;

/** A float in [0, 1) for stream `index` of `seed` (the splitmix32 finalizer of seed + index). */
export function unitRandom( seed, index ) {

	let z = ( seed + Math.imul( index + 1, 0x9e3779b9 ) ) >>> 0;
	z = Math.imul( z ^ ( z >>> 16 ), 0x85ebca6b ) >>> 0;
	z = Math.imul( z ^ ( z >>> 13 ), 0xc2b2ae35 ) >>> 0;
	z = ( z ^ ( z >>> 16 ) ) >>> 0;
	return z / 4294967296;

}
