// The lighting the fur shaders take (crates/pelt-render/src/lighting.rs `Lighting`, `KajiyaKay`, `Prt`, and
// what `Lighting::frame` hands the shaders), with the preview's defaults. Directions are in
// three.js world space: the preview's default light, (0.4, −0.5, 0.75) in Pelt's Z-up object
// space, is turned into glTF's Y-up world as the add-on turns objects, (x, y, z) → (x, z, −y).

import { capBandWeights } from './sh.js';

export const DEFAULT_LIGHTING = Object.freeze( {
	// Toward the light; any non-zero length.
	direction: [ 0.4, 0.75, 0.5 ],
	// Irradiance on a surface facing the light × its color (Blender's sun strength): π lights a
	// white Lambertian surface facing it to 1.
	color: [ Math.PI, Math.PI, Math.PI ],
	// Banks-style self-shadowing, [0, 1] (Kajiya–Kay only).
	selfShadow: 0.15,
	// 'auto' (PRT where the file has transfer textures of order ≤ MAX_PRT_ORDER, else
	// Kajiya–Kay), 'kajiya-kay' or 'prt'.
	model: 'auto',
	kajiyaKay: Object.freeze( {
		ambient: [ 0.12, 0.12, 0.12 ],
		// The ambient's change per unit of the normal's x, y and z (rows, linear RGB, world space):
		// a sky brighter above lights fur facing up more. Zero: a uniform ambient.
		ambientGradient: [ [ 0, 0, 0 ], [ 0, 0, 0 ], [ 0, 0, 0 ] ],
		diffuse: 0.9,
		specular: 0.25,
		diffusePower: 1,
		specularPower: 48,
	} ),
	prt: Object.freeze( {
		// A uniform sky of this radiance (linear RGB): the preview's default environment, which
		// holds the constant SH coefficient only.
		sky: [ 0.1, 0.1, 0.1 ],
		// Angular radius of the directional light's cap, radians.
		lightRadius: 0.2,
	} ),
} );

/** `options` over the defaults, one level deep for the model blocks. */
export function resolveLighting( options = {} ) {

	return {
		...DEFAULT_LIGHTING,
		...options,
		kajiyaKay: { ...DEFAULT_LIGHTING.kajiyaKay, ...options.kajiyaKay },
		prt: { ...DEFAULT_LIGHTING.prt, ...options.prt },
	};

}

/**
 * Highest SH order the PRT path takes: each vertex hands its lighting to the fragments in
 * ⌈n² / 4⌉ vec4s, within WebGL 2's 15 varying vectors for n ≤ 6.
 */
export const MAX_PRT_ORDER = 6;

/** Whether `lighting` shades a stack with PRT ('auto': where the stack has a transfer within reach). */
export function usesPrt( lighting, stack ) {

	if ( lighting.model === 'prt' ) {

		if ( ! stack.transfer ) throw new Error( 'PELT_shell_fur: lighting.model "prt" needs a stack with transfer textures' );
		if ( stack.transfer.order > MAX_PRT_ORDER ) {

			throw new Error( `PELT_shell_fur: PRT of order ${stack.transfer.order} exceeds this runtime's ${MAX_PRT_ORDER}; use lighting.model "kajiya-kay"` );

		}

		return true;

	}

	return lighting.model === 'auto' && !! stack.transfer && stack.transfer.order <= MAX_PRT_ORDER;

}

/**
 * The uniform values of `lighting` (lighting.rs `Lighting::frame`): the unit direction, the color
 * over π, and per model its terms; for PRT of `order` bands the sky's constant coefficient and the
 * cap's per-band weights, both over π (prt_light.rs `world_coefficients`), the light's share
 * of the lighting, which its hot spot clears of the transfer's shadow, and the sky as the
 * ambient of bald skin.
 */
export function lightingValues( lighting, order = 0 ) {

	const d = lighting.direction;
	const len = Math.hypot( d[ 0 ], d[ 1 ], d[ 2 ] );
	if ( ! ( len > 0 && Number.isFinite( len ) ) ) throw new Error( 'PELT_shell_fur: lighting.direction must be finite and non-zero' );
	const kk = lighting.kajiyaKay;
	const values = {
		direction: d.map( ( c ) => c / len ),
		color: lighting.color.map( ( c ) => c / Math.PI ),
		ambient: kk.ambient,
		ambientGradient: kk.ambientGradient,
		kajiyaKay: [ kk.diffuse, kk.specular, kk.diffusePower, kk.specularPower ],
		selfShadow: Math.min( Math.max( lighting.selfShadow, 0 ), 1 ),
	};
	if ( order > 0 ) {

		// The sky's Y_0^0 coefficient is √(4π) × its radiance; the 1/π is folded in as the preview does.
		values.sky = lighting.prt.sky.map( ( c ) => Math.sqrt( 4 * Math.PI ) * c / Math.PI );
		values.capWeights = capBandWeights( order, lighting.prt.lightRadius );
		// lighting.rs hot_spot_share(): the light's irradiance over that plus the sky's × π.
		const sun = values.color.reduce( ( a, c ) => a + c, 0 );
		const sky = lighting.prt.sky.reduce( ( a, c ) => a + Math.max( c, 0 ), 0 );
		values.hotSpotShare = sun > 0 ? sun / ( sun + sky ) : 0;
		// Bald skin is Kajiya–Kay's (surface_prt.wgsl bare_skin): lit by the sky's irradiance
		// over π, its radiance for a uniform sky.
		values.ambient = lighting.prt.sky;
		values.ambientGradient = [ [ 0, 0, 0 ], [ 0, 0, 0 ], [ 0, 0, 0 ] ];

	}

	return values;

}
