# Builds MATIEC's iec2c (third_party/matiec, GPL-3) without autotools: only the compiler
# the tests need, not iec2iec. tasks.py copies the sources into build/matiec/src and runs
#     make -f third_party/matiec.mk -C build/matiec/src -j2
# there, so the generated parser and the objects stay out of the sources and out of git.
CXX ?= g++
# -O0 and no -g: the build runs on every fresh clone and CI machine, and iec2c compiles
# programs of a few hundred lines in well under a second unoptimised
CXXFLAGS ?= -O0 -w
DEFS = -DPACKAGE_NAME='"matiec"' -DPACKAGE_VERSION='"d319624"' -DHGVERSION='"d319624"'

ABSYNTAX = absyntax/absyntax.cc absyntax/visitor.cc
UTILS = $(addprefix absyntax_utils/, absyntax_utils.cc add_en_eno_param_decl.cc \
	decompose_var_instance_name.cc array_dimension_iterator.cc case_element_iterator.cc \
	function_call_iterator.cc function_call_param_iterator.cc function_param_iterator.cc \
	get_sizeof_datatype.cc get_var_name.cc search_il_label.cc search_base_type.cc \
	search_fb_instance_decl.cc search_fb_typedecl.cc search_varfb_instance_type.cc \
	search_var_instance_decl.cc spec_init_separator.cc type_initial_value.cc debug_ast.cc \
	get_datatype_info.cc)
STAGE12 = stage1_2/iec_bison.cc stage1_2/iec_flex.cc \
	stage1_2/create_enumtype_conversion_functions.cc stage1_2/stage1_2.cc
STAGE3 = $(addprefix stage3/, stage3.cc flow_control_analysis.cc fill_candidate_datatypes.cc \
	narrow_candidate_datatypes.cc forced_narrow_candidate_datatypes.cc \
	print_datatypes_error.cc datatype_functions.cc lvalue_check.cc array_range_check.cc \
	case_elements_check.cc constant_folding.cc declaration_check.cc \
	enum_declaration_check.cc remove_forward_dependencies.cc)
STAGE4 = stage4/stage4.cc stage4/generate_c/generate_c.cc
OBJS = $(patsubst %.cc,%.o,main.cc $(ABSYNTAX) $(UTILS) $(STAGE12) $(STAGE3) $(STAGE4))

iec2c: $(OBJS)
	$(CXX) -o $@ $(OBJS)

config/config.h:
	mkdir -p config && : > $@

stage1_2/iec_bison.cc stage1_2/iec_bison.hh: stage1_2/iec_bison.yy
	bison -d -o stage1_2/iec_bison.cc $<

stage1_2/iec_flex.cc: stage1_2/iec_flex.ll stage1_2/iec_bison.hh
	flex -o $@ $<

stage1_2/%.o: stage1_2/%.cc stage1_2/iec_bison.hh
	$(CXX) $(CXXFLAGS) $(DEFS) -I$(<D) -DDEFAULT_LIBDIR='"lib"' -DYY_BUF_SIZE=65536 -fpermissive \
		-Iabsyntax -c -o $@ $<

stage4/generate_c/%.o: stage4/generate_c/%.cc
	$(CXX) $(CXXFLAGS) $(DEFS) -I$(<D) -Iabsyntax -c -o $@ $<

%.o: %.cc config/config.h stage1_2/iec_bison.hh
	$(CXX) $(CXXFLAGS) $(DEFS) -I$(<D) -c -o $@ $<
