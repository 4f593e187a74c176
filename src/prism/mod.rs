//! `refract prism`: report 000, white light dispersed by an Amici
//! direct-vision prism, rendered by photon mapping: a light pass deposits
//! photons (each with its own wavelength once something disperses) on the
//! matte surfaces, an eye pass without Phong reads the colour back.

pub mod amici;
pub mod probe;
pub mod scene;
pub mod scenes;
pub mod trace;
