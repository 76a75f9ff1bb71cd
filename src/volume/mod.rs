//! The hair volume: strands sampled into the layers of a tileable shell texture.
//!
//! Lengyel et al. 2001, §2.2 sample the geometric hair of one toroidal tile into an RGBA image per
//! shell layer; the PRT shell-fur paper (`prt-shell-fur`, §2.1) computes each hair's contribution
//! to a texel as the share of the texel its cross-section covers, so that hairs do not jump from
//! texel to texel between layers. This module holds that sampling, one stage per file. Today:
//! [`coverage`], the area a hair's circular cross-section covers in each texel of a layer.

pub mod coverage;
