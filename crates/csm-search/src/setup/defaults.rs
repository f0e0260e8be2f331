//! Kratos' default parameters, as the Python layer and the C++ wrapper declare them.

/// `ALMContactProcess` defaults (Kratos 10.4.4 `alm_contact_process.py`), recursively
/// validated by Kratos.
pub(crate) const ALM_DEFAULTS: &str = r#"{
    "help": "",
    "model_part_name": "Structure",
    "contact_model_part": {"0":[],"1":[],"2":[],"3":[],"4":[],"5":[],"6":[],"7":[],"8":[],"9":[]},
    "assume_master_slave": {"0":[],"1":[],"2":[],"3":[],"4":[],"5":[],"6":[],"7":[],"8":[],"9":[]},
    "contact_property_ids": {"0":0,"1":0,"2":0,"3":0,"4":0,"5":0,"6":0,"7":0,"8":0,"9":0},
    "friction_coefficients": {"0":0.0,"1":0.0,"2":0.0,"3":0.0,"4":0.0,"5":0.0,"6":0.0,"7":0.0,"8":0.0,"9":0.0},
    "contact_type": "Frictionless",
    "not_normal_update_frictional": false,
    "interval": [0.0, "End"],
    "normal_variation": "no_derivatives_computation",
    "frictional_law": "Coulomb",
    "tangent_factor": 2.5e-2,
    "operator_threshold": 1.0e-3,
    "slip_augmentation_coefficient": 0.0,
    "slip_threshold": 2.0e-2,
    "zero_tolerance_factor": 1.0,
    "integration_order": 2,
    "consider_tessellation": false,
    "normal_check_proportion": 0.1,
    "clear_inactive_for_post": true,
    "slip_step_reset_frequency": 1,
    "search_parameters": {
        "type_search": "in_radius_with_obb",
        "simple_search": false,
        "adapt_search": false,
        "search_factor": 3.5,
        "active_check_factor": 0.01,
        "max_number_results": 1000,
        "bucket_size": 4,
        "dynamic_search": false,
        "static_check_movement": false,
        "database_step_update": 1,
        "normal_orientation_threshold": 1.0e-1,
        "consider_gap_threshold": false,
        "debug_mode": false,
        "predict_correct_lagrange_multiplier": false,
        "check_gap": "check_mapping",
        "octree_search_parameters": {
            "bounding_box_factor": 0.1,
            "debug_obb": false,
            "OBB_intersection_type": "SeparatingAxisTheorem",
            "build_from_bounding_box": true,
            "lower_bounding_box_coefficient": 0.0,
            "higher_bounding_box_coefficient": 1.0
        }
    },
    "advance_explicit_parameters": {
        "manual_max_gap_theshold": false,
        "automatic_gap_factor": 1.0e-1,
        "max_gap_threshold": 5.0e-2,
        "max_gap_factor": 1.0e2,
        "logistic_exponent_factor": 6.0
    },
    "advance_ALM_parameters": {
        "manual_ALM": false,
        "stiffness_factor": 1.0,
        "penalty_scale_factor": 1.0,
        "use_scale_factor": true,
        "penalty": 1.0e-12,
        "scale_factor": 1.0e0,
        "adapt_penalty": false,
        "max_gap_factor": 1.0e-3
    },
    "alternative_formulations": {
        "axisymmetric": false
    }
}"#;

/// `ContactSearchWrapperProcess::GetDefaultParameters` (C++ users, `cpp_search_parameters`),
/// recursively validated by the wrapper. Note `normal_orientation_threshold` 1e-8 and
/// `type_search` `"InRadius"` here (Q5).
pub(crate) const WRAPPER_DEFAULTS: &str = r#"{
    "simple_search": false,
    "allocation_size": 1000,
    "bucket_size": 4,
    "search_factor": 3.5,
    "type_search": "InRadius",
    "check_gap": "MappingCheck",
    "condition_name": "",
    "final_string": "",
    "inverted_search": false,
    "dynamic_search": false,
    "static_check_movement": false,
    "predefined_master_slave": true,
    "id_name": "",
    "normal_orientation_threshold": 1.0e-8,
    "consider_gap_threshold": false,
    "predict_correct_lagrange_multiplier": false,
    "pure_slip": false,
    "debug_mode": false,
    "octree_search_parameters": {
        "bounding_box_factor": 0.1,
        "debug_obb": false,
        "OBB_intersection_type": "SeparatingAxisTheorem",
        "build_from_bounding_box": true,
        "lower_bounding_box_coefficient": 0.0,
        "higher_bounding_box_coefficient": 1.0
    }
}"#;

/// `MPCContactProcess` defaults (Kratos 10.4.4 `mpc_contact_process.py`), recursively
/// validated by Kratos.
pub(crate) const MPC_DEFAULTS: &str = r#"{
    "help": "",
    "model_part_name": "Structure",
    "contact_model_part": {"0":[],"1":[],"2":[],"3":[],"4":[],"5":[],"6":[],"7":[],"8":[],"9":[]},
    "assume_master_slave": {"0":[],"1":[],"2":[],"3":[],"4":[],"5":[],"6":[],"7":[],"8":[],"9":[]},
    "contact_property_ids": {"0":0,"1":0,"2":0,"3":0,"4":0,"5":0,"6":0,"7":0,"8":0,"9":0},
    "friction_coefficients": {"0":0.0,"1":0.0,"2":0.0,"3":0.0,"4":0.0,"5":0.0,"6":0.0,"7":0.0,"8":0.0,"9":0.0},
    "contact_type": "Frictionless",
    "not_normal_update_frictional": false,
    "interval": [0.0, "End"],
    "normal_variation": "no_derivatives_computation",
    "frictional_law": "Coulomb",
    "tangent_factor": 1.0e-1,
    "zero_tolerance_factor": 1.0e2,
    "reaction_check_stiffness_factor": 1.0e-10,
    "integration_order": 2,
    "consider_tessellation": false,
    "normal_check_proportion": 0.1,
    "clear_inactive_for_post": true,
    "update_condition_relation_step": false,
    "search_parameters": {
        "type_search": "in_radius_with_obb",
        "simple_search": false,
        "adapt_search": false,
        "search_factor": 3.5,
        "active_check_factor": 0.01,
        "max_number_results": 1000,
        "bucket_size": 4,
        "dynamic_search": false,
        "static_check_movement": false,
        "database_step_update": 1,
        "normal_orientation_threshold": 1.0e-1,
        "consider_gap_threshold": false,
        "debug_mode": false,
        "predict_correct_lagrange_multiplier": false,
        "check_gap": "check_mapping",
        "octree_search_parameters": {
            "bounding_box_factor": 0.1,
            "debug_obb": false,
            "OBB_intersection_type": "SeparatingAxisTheorem",
            "build_from_bounding_box": true,
            "lower_bounding_box_coefficient": 0.0,
            "higher_bounding_box_coefficient": 1.0
        }
    }
}"#;

/// `MeshTyingProcess` defaults (Kratos 10.4.4 `mesh_tying_process.py`). Kratos validates
/// them without recursion: a `search_parameters` object the user gives is kept whole and
/// completed by `SearchBaseProcess` with the base defaults (the `search_parameters` of
/// [`ALM_DEFAULTS`], which are the base's), so `database_step_update` is 999999999 only when
/// the user gives no `search_parameters` at all.
pub(crate) const MESH_TYING_DEFAULTS: &str = r#"{
    "help": "",
    "model_part_name": "Structure",
    "mesh_tying_model_part": {"0":[],"1":[],"2":[],"3":[],"4":[],"5":[],"6":[],"7":[],"8":[],"9":[]},
    "assume_master_slave": {"0":[],"1":[],"2":[],"3":[],"4":[],"5":[],"6":[],"7":[],"8":[],"9":[]},
    "mesh_tying_property_ids": {"0":0,"1":0,"2":0,"3":0,"4":0,"5":0,"6":0,"7":0,"8":0,"9":0},
    "interval": [0.0, "End"],
    "variable_name": "DISPLACEMENT",
    "consider_static_condensation": false,
    "zero_tolerance_factor": 1.0,
    "integration_order": 2,
    "consider_tessellation": true,
    "normal_check_proportion": 0.1,
    "search_parameters": {
        "type_search": "in_radius_with_obb",
        "search_factor": 3.5,
        "active_check_factor": 0.01,
        "max_number_results": 1000,
        "bucket_size": 4,
        "dynamic_search": false,
        "database_step_update": 999999999,
        "debug_mode": false,
        "check_gap": "check_mapping",
        "octree_search_parameters": {
            "bounding_box_factor": 0.1,
            "debug_obb": false,
            "OBB_intersection_type": "SeparatingAxisTheorem",
            "lower_bounding_box_coefficient": 0.0,
            "higher_bounding_box_coefficient": 1.0
        }
    },
    "scale_factor_parameters": {
        "manual_scale_factor": false,
        "stiffness_factor": 1.0,
        "scale_factor": 1.0e0
    }
}"#;

/// The top-level keys csm adds to Kratos' parameters (DESIGN.md §2).
pub(crate) const CSM_KEYS: [&str; 9] = [
    "compatibility",
    "process",
    "strict",
    "process_info",
    "nodal_h",
    "cpp_search_parameters",
    "steps",
    "nodal_values",
    "refit_tree",
];

/// `python_module`s of the contact processes whose `Parameters` a ProjectParameters file can
/// hold; the first found is used.
pub(crate) const CONTACT_MODULES: [&str; 5] = [
    "alm_contact_process",
    "penalty_contact_process",
    "explicit_penalty_contact_process",
    "mpc_contact_process",
    "mesh_tying_process",
];
