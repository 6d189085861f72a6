//! System identification from step responses.
