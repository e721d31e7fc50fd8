//! # acsg: Assembly Contact State Graphs of two polyhedral parts
//!
//! Part A is held fixed, part B is carried by a robot whose misalignment is bounded.
//! `acsg` reads both parts, builds their exact boundary representation (faces with
//! holes, edges, vertices, convexity, convex pieces) and, from there, the contact
//! states that can occur within the bounds.
//!
//! ```
//! use acsg::model::Part;
//!
//! let (fixed, moving) = acsg::examples::l_block_and_box();
//! assert_eq!((fixed.faces().len(), fixed.edges().len(), fixed.vertices().len()), (8, 18, 12));
//! assert_eq!(acsg::model::ppc_count(&fixed, &moving).total(), 328);
//! ```
#![warn(missing_docs)]

pub mod contact;
pub mod examples;
pub mod export;
pub mod feasibility;
pub mod geometry;
pub mod graph;
pub mod io;
pub mod load;
pub mod model;
pub mod pose;
pub mod task;
pub mod tolerance;
pub mod units;
